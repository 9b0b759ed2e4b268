#pragma once
// The PointSource of slaves whose device model is known: every value a frame carries, named
// and scaled by the slave's map ("F" = 50.01 Hz instead of "holding 0x0036" = 46822), decoded
// by the RegisterDecoder with what has been learned about the slave so far (PT, CT). Slaves
// without a map are handed to a fallback source (raw registers), so one report can mix both.
//
// Which values are delivered, and when: the same as the raw source. Reads on their normal
// response (the request gives the range), writes on the normal response that confirms them,
// at the response's start time. Only whole points with a value are delivered: addresses the
// map does not define, spare registers and points a transfer cuts in half are left out.
// Bit fields and enums are delivered as the point's number; values are rounded to the
// point's decimals, as `decode` shows them.
#include <array>
#include <cstdint>

#include "dissect/device_map.hpp"
#include "dissect/map_identifier.hpp"
#include "dissect/register_decoder.hpp"
#include "report/point_source.hpp"

namespace rtu::dissect {

// Where a slave's model came from.
enum class ModelOrigin : std::uint8_t {
  kConfigured,  // --device, --bus
  kIdentified,  // ranked first by the MapIdentifier, confidently
};

class DevicePointSource : public PointSource {
 public:
  // `fallback` (not owned, may be null) handles the slaves without a map.
  explicit DevicePointSource(PointSource* fallback) : fallback_(fallback) {}

  // `map` must outlive the source (MapLibrary keeps maps at stable addresses).
  void assign(std::uint8_t slave, const DeviceMap& map, ModelOrigin origin);
  [[nodiscard]] const DeviceMap* map_of(std::uint8_t slave) const { return slaves_[slave].map; }
  // Gives every slave without a map the one `ranking` names with confidence (confident_map),
  // as identified. Works at any time: values from then on are named (a live run can call it
  // before its report, so the model at least is shown).
  void assign_identified(const std::vector<SlaveRanking>& ranking);

  void extract(const Record& frame, PointSink& sink) override;
  [[nodiscard]] std::string_view device_model(std::uint8_t slave) const override;
  [[nodiscard]] bool device_model_identified(std::uint8_t slave) const override;
  [[nodiscard]] std::string_view device_exception_name(std::uint8_t slave,
                                                       std::uint8_t code) const override;

 private:
  struct Slave {
    const DeviceMap* map = nullptr;
    ModelOrigin origin = ModelOrigin::kConfigured;
    SlaveState state;
  };
  void deliver(const Record& frame, const Decoded& decoded, PointSink& sink) const;

  PointSource* fallback_;
  std::array<Slave, 256> slaves_{};
  RegisterDecoder decoder_;
  Decoded decoded_;  // reused, so steady state does not allocate
  Decoded learned_;  // what a confirming write response taught (values come from its request)
};

}  // namespace rtu::dissect

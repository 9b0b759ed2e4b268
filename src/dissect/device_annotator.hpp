#pragma once
// The FrameAnnotator of device maps: knows which model each slave is, decodes every frame
// of a known slave with the RegisterDecoder, and tells the writers what to add
// ("device", "registers", vendor exception names). Frames of unknown slaves pass untouched.
#include <array>
#include <cstdint>
#include <optional>

#include "dissect/device_map.hpp"
#include "dissect/register_decoder.hpp"
#include "report/frame_annotator.hpp"

namespace rtu::dissect {

class DeviceAnnotator : public FrameAnnotator {
 public:
  // `map` must outlive the annotator (MapLibrary keeps maps at stable addresses).
  void assign(std::uint8_t slave, const DeviceMap& map);
  [[nodiscard]] const DeviceMap* model_of(std::uint8_t slave) const { return slaves_[slave].map; }
  [[nodiscard]] bool empty() const;

  void annotate(Record& frame) override;
  void write_json(JsonWriter& json, const Record& frame) const override;
  void append_text(fmt::memory_buffer& out, const Record& frame) const override;
  [[nodiscard]] std::string_view exception_name(const Record& frame,
                                                std::uint8_t code) const override;

  // The decode of a frame annotated recently (the last few), or null.
  [[nodiscard]] const Decoded* decoded(const Record& frame) const;

 private:
  struct Slave {
    const DeviceMap* map = nullptr;
    SlaveState state;
  };
  struct Slot {
    std::optional<std::uint64_t> seq;
    Decoded decoded;
  };
  std::array<Slave, 256> slaves_{};
  // Writers ask about a frame right after annotating it; a few slots are kept so that a
  // request and its response can both be asked about. Reused, so steady state never
  // allocates.
  std::array<Slot, 4> slots_{};
  RegisterDecoder decoder_;
};

}  // namespace rtu::dissect

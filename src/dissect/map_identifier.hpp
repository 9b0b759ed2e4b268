#pragma once
// Which device model is each slave? Ranks the available maps per slave by how well they
// explain the traffic seen: function codes the map lists, addresses it defines (and
// exceptions that reject what it does not), values inside its documented ranges and enums.
// A record sink: feed it a whole capture, then ask for the ranking.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "dissect/map_library.hpp"
#include "dissect/register_decoder.hpp"
#include "framing/record.hpp"

namespace rtu::dissect {

struct MapEvidence {
  const DeviceMap* map = nullptr;
  std::uint64_t requests = 0;
  std::uint64_t listed_function = 0;    // requests whose function code the map lists
  std::uint64_t rejected_function = 0;  // unlisted, and the slave answered "bad function"
  std::uint64_t units = 0;              // addresses requested (registers, bytes or bits)
  std::uint64_t defined_units = 0;      // of which the map defines
  std::uint64_t rejected_units = 0;     // undefined, and the slave answered "bad address"
  std::uint64_t values_in = 0;          // values inside a documented range or enum
  std::uint64_t values_out = 0;         // values outside it
  std::uint64_t scale_hits = 0;         // learned vars seen (e.g. PT read)
  double score = 0.0;                   // 0..100

  void compute_score();
};

struct SlaveRanking {
  std::uint8_t slave = 0;
  std::uint64_t requests = 0;
  std::vector<MapEvidence> maps;  // best first
};

class MapIdentifier : public RecordSink {
 public:
  // `requests_per_slave`: once a slave has sent that many requests, its evidence is complete
  // and later frames of it are left aside (0 = weigh every frame), so that identifying costs
  // a bounded effort per slave however busy the bus is.
  explicit MapIdentifier(const MapLibrary& library, std::uint64_t requests_per_slave = 0)
      : library_(library), requests_per_slave_(requests_per_slave) {}
  void on_record(Record& record) override;
  [[nodiscard]] std::vector<SlaveRanking> ranking() const;

 private:
  struct Candidate {
    MapEvidence evidence;
    SlaveState state;
  };
  void on_request(const Record& request, std::vector<Candidate>& candidates);
  void on_response(const Record& response, std::vector<Candidate>& candidates);

  const MapLibrary& library_;
  std::uint64_t requests_per_slave_;
  std::map<std::uint8_t, std::vector<Candidate>> slaves_;
  RegisterDecoder decoder_;
  Decoded decoded_;
};

// The map `ranking` names with confidence, or null. Confident means: at least
// kConfidentRequests requests, the best map explains (nearly) all of them (score ≥
// kConfidentScore), and no other map comes within kConfidentMargin points of it. A bus
// where one address is shared by several models, or a slave asked only a few questions,
// stays unidentified.
inline constexpr std::uint64_t kConfidentRequests = 10;
inline constexpr double kConfidentScore = 99.0;
inline constexpr double kConfidentMargin = 0.5;
const DeviceMap* confident_map(const SlaveRanking& ranking);

// How much of an address range a space defines, in the space's units.
struct Coverage {
  std::uint32_t units = 0;
  std::uint32_t defined = 0;
};
Coverage coverage(const Space& space, std::uint32_t start, std::uint32_t quantity,
                  bool registers_quantity);

}  // namespace rtu::dissect

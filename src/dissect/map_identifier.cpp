#include "dissect/map_identifier.hpp"

#include <algorithm>
#include <cmath>

#include "modbus/data_access.hpp"

namespace rtu::dissect {
namespace {

// How many of a space's addresses a request's ranges cover. A register quantity spans two
// addresses of a byte-addressed space.
Coverage access_coverage(const Space& space, const DataAccess& access) {
  Coverage total;
  for (const DataBlock& b : access) {
    const Coverage c = coverage(space, b.addr, b.qty, !is_bit_table(b.table));
    total.units += c.units;
    total.defined += c.defined;
  }
  return total;
}

bool contains(std::string_view text, std::string_view word) {
  return text.find(word) != std::string_view::npos;
}

// Whether an exception code says "function not supported" or "address not there", in the
// map's own table when it has one (YAKOTEC: 02, 03/04), else the standard 01 / 02.
bool rejects_function(const DeviceMap& map, std::uint8_t code) {
  if (map.exceptions.empty()) return code == 1;
  return contains(map.exception_name(code), "function");
}
bool rejects_address(const DeviceMap& map, std::uint8_t code) {
  if (map.exceptions.empty()) return code == 2;
  return contains(map.exception_name(code), "address");
}

}  // namespace

Coverage coverage(const Space& space, std::uint32_t start, std::uint32_t quantity,
                  bool registers_quantity) {
  Coverage c;
  const bool bytewise = space.addressing == Addressing::kByte && registers_quantity;
  c.units = bytewise ? quantity * 2 : quantity;
  // Addresses end at 0xFFFF: a range running past it covers none beyond.
  c.defined = space.defined_in(start, std::min<std::uint32_t>(start + c.units, 0x10000U));
  return c;
}

void MapEvidence::compute_score() {
  if (requests == 0) {
    score = 0.0;
    return;
  }
  const double s_fc =
      static_cast<double>(listed_function + rejected_function) / static_cast<double>(requests);
  const double s_addr =
      units == 0 ? s_fc
                 : static_cast<double>(defined_units + rejected_units) / static_cast<double>(units);
  // Laplace-smoothed, so one value proves little either way.
  const double s_val =
      static_cast<double>(values_in + 1) / static_cast<double>(values_in + values_out + 1);
  score = 100.0 * s_fc * s_addr * s_val;
}

void MapIdentifier::on_record(Record& record) {
  if (record.kind != RecordKind::kFrame || !record.crc_ok || record.size < 4) return;
  if (record.role == Role::kRequest && record.slave() == 0) return;  // broadcast: no model
  const std::uint8_t slave = record.slave();
  auto [it, inserted] = slaves_.try_emplace(slave);
  if (inserted) {
    for (const auto& map : library_.maps()) {
      Candidate c;
      c.evidence.map = map.get();
      c.state.reset(*map);
      it->second.push_back(std::move(c));
    }
  }
  std::vector<Candidate>& candidates = it->second;
  if (requests_per_slave_ > 0 && !candidates.empty() &&
      candidates.front().evidence.requests >= requests_per_slave_) {
    return;
  }
  if (record.role == Role::kRequest) on_request(record, candidates);
  if (record.role == Role::kResponse && record.request != nullptr) {
    on_response(record, candidates);
  }
}

void MapIdentifier::on_request(const Record& request, std::vector<Candidate>& candidates) {
  const DataAccess access = data_access(request, nullptr);
  for (auto& c : candidates) {
    const DeviceMap& map = *c.evidence.map;
    ++c.evidence.requests;
    const Space* space = map.space_for(request.function());
    if (space == nullptr) continue;
    ++c.evidence.listed_function;
    const Coverage cov = access_coverage(*space, access);
    c.evidence.units += cov.units;
    c.evidence.defined_units += cov.defined;
    decoder_.decode(map, c.state, request, &access, decoded_);
    for (const auto& p : decoded_.points) {
      if (p.point == nullptr || !p.has_value || p.spare_index > 0) continue;
      const bool ranged = p.point->min.has_value() || !p.point->enums.empty();
      if (!ranged) continue;
      bool in = true;
      if (p.point->min && (p.base < *p.point->min || p.base > *p.point->max)) in = false;
      if (!p.point->enums.empty() &&
          find_enum(*p.point, raw_as_integer(*p.point, p.raw)) == nullptr) {
        in = false;
      }
      ++(in ? c.evidence.values_in : c.evidence.values_out);
    }
  }
}

void MapIdentifier::on_response(const Record& response, std::vector<Candidate>& candidates) {
  const Record& request = *response.request;
  const DataAccess access = data_access(request, nullptr);
  for (auto& c : candidates) {
    const DeviceMap& map = *c.evidence.map;
    const Space* space = map.space_for(request.function());
    if (response.is_exception()) {
      const std::uint8_t code = response.storage[2];
      if (space == nullptr && rejects_function(map, code)) ++c.evidence.rejected_function;
      if (space != nullptr && rejects_address(map, code)) {
        const Coverage cov = access_coverage(*space, access);
        c.evidence.rejected_units += cov.units - cov.defined;
      }
      continue;
    }
    if (space == nullptr) continue;
    decoder_.decode(map, c.state, response, decoded_);
    for (const auto& p : decoded_.points) {
      if (p.point == nullptr || !p.has_value || p.spare_index > 0) continue;
      if (p.point->learn) ++c.evidence.scale_hits;
      const bool ranged = p.point->min.has_value() || !p.point->enums.empty();
      if (!ranged) continue;
      bool in = true;
      if (p.point->min && (p.base < *p.point->min || p.base > *p.point->max)) in = false;
      if (!p.point->enums.empty() &&
          find_enum(*p.point, raw_as_integer(*p.point, p.raw)) == nullptr) {
        in = false;
      }
      ++(in ? c.evidence.values_in : c.evidence.values_out);
    }
  }
}

std::vector<SlaveRanking> MapIdentifier::ranking() const {
  std::vector<SlaveRanking> out;
  for (const auto& [slave, candidates] : slaves_) {
    SlaveRanking r;
    r.slave = slave;
    for (const auto& c : candidates) {
      MapEvidence e = c.evidence;
      e.compute_score();
      r.requests = e.requests;
      r.maps.push_back(e);
    }
    if (r.requests == 0) continue;  // only responses seen (e.g. unsolicited)
    std::stable_sort(r.maps.begin(), r.maps.end(), [](const MapEvidence& a, const MapEvidence& b) {
      if (a.score != b.score) return a.score > b.score;
      return a.map->model < b.map->model;
    });
    out.push_back(std::move(r));
  }
  return out;
}

const DeviceMap* confident_map(const SlaveRanking& ranking) {
  if (ranking.requests < kConfidentRequests || ranking.maps.empty()) return nullptr;
  const MapEvidence& best = ranking.maps.front();
  if (best.score < kConfidentScore) return nullptr;
  if (ranking.maps.size() > 1 && ranking.maps[1].score > best.score - kConfidentMargin) {
    return nullptr;
  }
  return best.map;
}

}  // namespace rtu::dissect

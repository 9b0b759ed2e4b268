#include "capture_checks.hpp"

#include <exception>
#include <string>

#include "core/input_error.hpp"
#include "fuzz_oracle.hpp"

namespace rtu::fuzz {
namespace {

class CheckingConsumer final : public CaptureConsumer {
 public:
  CheckingConsumer(const CaptureRules& rules, CaptureRead& out) : rules_(rules), out_(out) {}

  void on_chunk(const Chunk& chunk) override {
    if (chunk.bytes.empty()) fail(rules_.target, "chunk without bytes", "");
    if (!chunk.errors.empty() && chunk.errors.size() != chunk.bytes.size()) {
      fail(rules_.target, "line errors not one per byte", "");
    }
    if (rules_.per_byte_exact) {
      if (chunk.bytes.size() != 1) fail(rules_.target, "per-byte chunk of several bytes", "");
      if (chunk.t_first_start == kUnknownTime) fail(rules_.target, "per-byte chunk untimed", "");
      if (chunk.t_first_start > chunk.t_end) fail(rules_.target, "chunk ends before it starts", "");
    }
    if (rules_.times_in_order) {
      const Nanos t = rules_.per_byte_exact ? chunk.t_first_start : chunk.t_end;
      if (have_last_ && t < last_t_) fail(rules_.target, "chunk times out of order", "");
      have_last_ = true;
      last_t_ = t;
    }
    check_origin(chunk.origin);
    CaptureItem item;
    item.kind = CaptureItem::Kind::kChunk;
    item.bytes.assign(chunk.bytes.begin(), chunk.bytes.end());
    item.errors.assign(chunk.errors.begin(), chunk.errors.end());
    item.t = chunk.t_end;
    item.t_first_start = chunk.t_first_start;
    item.origin = chunk.origin;
    item.port = chunk.port;
    out_.items.push_back(std::move(item));
  }

  void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) override {
    keep(CaptureItem::Kind::kFrame, adu, t_start, origin);
  }
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) override {
    keep(CaptureItem::Kind::kNoise, bytes, t_start, origin);
  }
  void on_end(Nanos t) override {
    CaptureItem item;
    item.kind = CaptureItem::Kind::kEnd;
    item.t = t;
    out_.items.push_back(std::move(item));
  }

 private:
  void keep(CaptureItem::Kind kind, std::span<const std::uint8_t> bytes, Nanos t_start,
            std::uint64_t origin) {
    check_origin(origin);
    CaptureItem item;
    item.kind = kind;
    item.bytes.assign(bytes.begin(), bytes.end());
    item.t = t_start;
    item.origin = origin;
    out_.items.push_back(std::move(item));
  }

  void check_origin(std::uint64_t origin) const {
    if (rules_.origins_are_lines) {
      if (origin < 1 || origin > count_lines(rules_.text)) {
        fail(rules_.target, "origin is not a line of the input", std::to_string(origin));
      }
    } else if (origin >= rules_.text.size()) {
      fail(rules_.target, "origin is past the end of the input", std::to_string(origin));
    }
  }

  const CaptureRules& rules_;
  CaptureRead& out_;
  bool have_last_ = false;
  Nanos last_t_ = 0;
};

}  // namespace

CaptureRead read_and_check(const ReaderFactory& open, const std::string& name,
                           const CaptureRules& rules) {
  CaptureRead out;
  const std::uint64_t lines = count_lines(rules.text);
  auto check_warning = [&](std::string_view message) {
    if (message.substr(0, name.size() + 1) != name + ":") {
      fail(rules.target, "warning does not name the input", message);
    }
  };
  std::unique_ptr<CaptureReader> reader;
  try {
    reader = open(check_warning);
    CheckingConsumer consumer(rules, out);
    const auto read = [&] {
      return rules.read_many_room == 0 ? reader->read(consumer)
                                       : reader->read_many(consumer, rules.read_many_room);
    };
    while (read()) {
    }
    // The end is sticky.
    if (read()) fail(rules.target, "item delivered after the end", "");
  } catch (const InputError& e) {
    if (rules.origins_are_lines) {
      require_line(rules.target, e.what(), name, lines);
    } else {
      require_offset(rules.target, e.what(), name, rules.text.size());
    }
    out.failed = true;
  } catch (const std::exception& e) {
    fail(rules.target, "exception other than InputError", e.what());
  } catch (...) {
    fail(rules.target, "exception other than InputError", "(not a std::exception)");
  }
  if (reader == nullptr) return out;
  if (out.failed && !rules.origins_are_lines) {
    // A pcap reader ends at the damage: nothing more after its error.
    try {
      CheckingConsumer after(rules, out);
      if (reader->read(after)) fail(rules.target, "item delivered after an error", "");
    } catch (const InputError& e) {
      fail(rules.target, "second error after the first", e.what());
    }
  }
  if (const auto line = reader->declared_settings()) {
    if (line->baud == 0 || (line->stop_bits != 1 && line->stop_bits != 2)) {
      fail(rules.target, "declared line settings out of range", "");
    }
  }
  if (reader->timestamp_precision() < 0) fail(rules.target, "negative timestamp precision", "");
  for (const auto& warning : reader->capture_warnings()) check_warning(warning);
  return out;
}

}  // namespace rtu::fuzz

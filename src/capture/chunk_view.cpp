#include "capture/chunk_view.hpp"

namespace rtu {
namespace {

class ChunkCatcher final : public CaptureConsumer {
 public:
  ChunkCatcher(Chunk& out, const CaptureReader& reader, LineSettings line)
      : out_(out), reader_(reader), line_(line) {}
  void on_chunk(const Chunk& chunk) override {
    out_ = chunk;
    caught = true;
  }
  void on_frame(std::span<const std::uint8_t> adu, Nanos t_start, std::uint64_t origin) override {
    record(adu, t_start, origin);
  }
  void on_noise(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) override {
    record(bytes, t_start, origin);
  }
  void on_end(Nanos /*t*/) override {}
  bool caught = false;

 private:
  void record(std::span<const std::uint8_t> bytes, Nanos t_start, std::uint64_t origin) {
    // Settings a capture declares are known once its first item was read, i.e. now.
    const Nanos char_time = reader_.declared_settings().value_or(line_).char_time();
    out_ = Chunk{};
    out_.t_first_start = t_start;
    out_.t_end = t_start + static_cast<Nanos>(bytes.size()) * char_time;
    out_.bytes = bytes;
    out_.origin = origin;
    caught = true;
  }
  Chunk& out_;
  const CaptureReader& reader_;
  LineSettings line_;
};

}  // namespace

ChunkView::ChunkView(CaptureReader& reader, LineSettings line) : reader_(reader), line_(line) {}

bool ChunkView::next(Chunk& out) {
  for (;;) {
    ChunkCatcher catcher(out, reader_, line_);
    if (!reader_.read(catcher)) return false;
    if (catcher.caught) return true;
  }
}

}  // namespace rtu

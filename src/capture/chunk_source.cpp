#include "capture/chunk_source.hpp"

#include <algorithm>

namespace rtu {

bool ChunkSource::read_many(CaptureConsumer& to, std::size_t max_reads) {
  if (at_end_) return false;
  if (!run_bytes_) {
    run_bytes_ = std::make_unique_for_overwrite<std::uint8_t[]>(kMaxRun);
    run_times_ = std::make_unique_for_overwrite<Nanos[]>(kMaxRun);
  }
  const std::size_t limit = std::clamp<std::size_t>(max_reads, 1, kMaxRun);
  ByteReads run;
  run.t_ends = run_times_.get();
  std::size_t size = 0;
  const auto deliver_run = [&] {
    if (size == 0) return;
    run.bytes = {run_bytes_.get(), size};
    to.on_byte_reads(run);
    size = 0;
  };
  std::size_t reads = 0;
  for (;;) {
    bool more = false;
    try {
      std::uint64_t origin = 0;
      const std::size_t got =
          next_byte_reads(run_bytes_.get() + size, run_times_.get() + size, limit - reads, origin);
      if (got > 0) {
        if (size > 0 && (run.port != 0 || origin != run.origin + size)) {
          // Not the run's next reads: the run goes first, and they start the next one.
          const std::size_t before = size;
          deliver_run();
          std::copy_n(run_bytes_.get() + before, got, run_bytes_.get());
          std::copy_n(run_times_.get() + before, got, run_times_.get());
        }
        if (size == 0) {
          run.origin = origin;
          run.port = 0;
        }
        size += got;
        reads += got;
        if (reads == limit) {
          deliver_run();
          return true;
        }
      }
      more = next(chunk_);
    } catch (...) {
      deliver_run();  // everything before the damage first
      throw;
    }
    if (!more) {
      at_end_ = true;
      deliver_run();
      return reads > 0;
    }
    ++reads;
    if (!ByteReads::holds(chunk_)) {
      deliver_run();
      to.on_chunk(chunk_);
      return true;
    }
    if (size > 0 && (chunk_.port != run.port || chunk_.origin != run.origin + size)) {
      deliver_run();
    }
    if (size == 0) {
      run.origin = chunk_.origin;
      run.port = chunk_.port;
    }
    run_bytes_[size] = chunk_.bytes[0];
    run_times_[size] = chunk_.t_end;
    ++size;
    if (reads == limit) {
      deliver_run();
      return true;
    }
  }
}

}  // namespace rtu

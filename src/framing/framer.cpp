#include "framing/framer.hpp"

#include <algorithm>
#include <cstring>
#include <span>

#include "core/crc16.hpp"
#include "core/function_codes.hpp"
#include "framing/crc_chain.hpp"
#include "framing/frame_classifier.hpp"
#include "framing/frame_shape.hpp"

namespace rtu {
namespace {

// How many frames with no length rule may vouch for each other in a row (vendor function
// codes polled back to back through a USB adapter). The last of them is vouched for by any
// CRC zero after it (Framer::generic_crc_length), so a chain is kGenericDepth + 1 CRC-valid
// spans back to back.
constexpr int kGenericDepth = 2;

// Role order to try: the one the bus state expects first.
struct RoleOrder {
  Role first;
  Role second;
};

}  // namespace

Framer::Framer(const FramerConfig& config, RecordSink& out)
    : config_(config),
      out_(out),
      char_time_(config.line.char_time()),
      t1_5_(config.line.t1_5()),
      t3_5_(config.line.t3_5()),
      resolution_(std::max<Nanos>(config.resolution, 0)) {
  noise_.kind = RecordKind::kNoise;
}

void Framer::expect_response_from(std::uint8_t slave, std::uint8_t function) {
  new_epoch();
  expect_response_ = true;
  expected_slave_ = slave;
  expected_function_ = function;
}

void Framer::expect_request() {
  new_epoch();
  expect_response_ = false;
}

// Slides the window back to the front; it never holds more than kMaxPending bytes.
void Framer::slide_window() {
  const std::size_t n = buffered();
  std::memmove(bytes_.data(), bytes_.data() + begin_, n);
  std::copy(info_.begin() + static_cast<std::ptrdiff_t>(begin_),
            info_.begin() + static_cast<std::ptrdiff_t>(end_), info_.begin());
  begin_ = 0;
  end_ = n;
}

void Framer::push_without_shortcut(const Chunk& chunk) {
  const std::size_t n = chunk.bytes.size();
  if (n == 0) return;
  if (const Nanos quiet = quiet_known_until(chunk); quiet != kUnknownTime) advance(quiet);
  last_read_filled_ = n >= kFullReadAtLeast && n >= largest_read_;
  largest_read_ = std::max(largest_read_, n);
  ++chunks_;
  if (n > 1) ++batched_chunks_;
  watching_reads_ = n < kCrcStepsUpTo || (n < kWatchedReadsUpTo && buffered() >= kWatchedStretch);
  const auto chunk_size = static_cast<std::uint16_t>(std::min<std::size_t>(n, UINT16_MAX));
  // Everything the loop reads, in locals: its stores into the byte window may alias anything
  // (they are uint8_t), so the compiler would otherwise reload each of these at every byte.
  // last_byte_end_ is only ever set here, to the `end` of the last byte stored.
  const std::uint8_t* const bytes = chunk.bytes.data();
  const std::uint8_t* const errors = chunk.errors.size() == n ? chunk.errors.data() : nullptr;
  const bool starts_measured = config_.per_byte_exact && chunk.t_first_start != kUnknownTime;
  // A clamped time says only that the read came after the one before, and a late read's
  // time is late by an unknown part of its delay: no silence is measured next to either.
  const bool time_known = !chunk.time_clamped && !chunk.read_late && !after_late_read_;
  after_late_read_ = chunk.read_late;
  const Nanos first_start = chunk.t_first_start;
  const Nanos read_end = chunk.t_end;
  const std::uint64_t origin = chunk.origin;
  const Nanos char_time = char_time_;
  Nanos last_end = last_byte_end_;
  // Byte i's end and the silence before it, the byte before having ended at last_end.
  const auto time_byte = [&](std::size_t i, Nanos& end, Nanos& gap) {
    gap = kUnknownTime;
    if (starts_measured) {
      // Measured start of the first byte; any further bytes follow back to back.
      const Nanos start = first_start + static_cast<Nanos>(i) * char_time;
      end = start + char_time;
      if (last_end != kUnknownTime && (i > 0 || time_known)) {
        gap = std::max<Nanos>(0, start - last_end);
      }
    } else if (i > 0) {
      // What the formula below gives once the read's first byte is placed (both sides of
      // its max grow by a character time a byte): back to back after the byte before.
      end = last_end + char_time;
    } else {
      // The read completed when the last byte had arrived; earlier bytes arrived at the
      // latest one character time apart, and never before the previous byte ended.
      end = read_end - static_cast<Nanos>(n - 1 - i) * char_time;
      if (last_end != kUnknownTime) {
        end = std::max(end, last_end + char_time);
        // Only a chunk boundary shows a silence; inside a chunk the bytes were batched.
        if (i == 0 && time_known) gap = end - char_time - last_end;
      }
    }
  };
  // The byte's position, a new one, is marked not looked at yet by the caller.
  const auto store_byte = [&](std::size_t i, Nanos end, Nanos gap) {
    bytes_[end_] = bytes[i];
    info_[end_] = ByteInfo{
        end, gap, origin, chunk_size, errors != nullptr ? errors[i] : std::uint8_t{0}, i == 0};
    ++end_;
  };
  if (n == 1) {
    // One byte (every read of a per-byte source): nothing to plan, and planning a stretch
    // cost such reads more than it saved them.
    if (end_ == kWindow) [[unlikely]] {
      slide_window();
    }
    Nanos end = 0;
    Nanos gap = kUnknownTime;
    time_byte(0, end, gap);
    settled_.clear((consumed_ + buffered()) % kWindow);
    store_byte(0, end, gap);
    last_byte_end_ = end;
    if (buffered() >= kMaxPending) [[unlikely]] {
      decide(false);
    }
    decide(false);
    return;
  }
  std::size_t i = 0;
  while (i < n) {
    if (end_ == kWindow) [[unlikely]] {
      slide_window();
    }
    // A stretch of bytes that neither reaches past the window's end nor forces a decision
    // before its last byte: the window's room and the forced decision are checked once a
    // stretch, not at every byte.
    const std::size_t pending = buffered();
    const std::size_t until_forced = pending < kMaxPending ? kMaxPending - pending : 1;
    const std::size_t stretch_end = i + std::min({n - i, kWindow - end_, until_forced});
    settled_.clear_run((consumed_ + pending) % kWindow, stretch_end - i);
    if (i == 0) {
      Nanos end = 0;
      Nanos gap = kUnknownTime;
      time_byte(0, end, gap);
      store_byte(0, end, gap);
      last_end = end;
      ++i;
    }
    if (!starts_measured) {
      // The bytes after a read's first were batched with it: back to back, no silence seen
      // (time_byte's second branch). In a loop of its own, without time_byte's branches and
      // with the bytes copied at once: this is most of the work a USB-chunked read costs.
      const std::size_t count = stretch_end - i;
      std::memcpy(bytes_.data() + end_, bytes + i, count);
      ByteInfo* const to = info_.data() + end_;
      for (std::size_t k = 0; k < count; ++k) {
        last_end += char_time;
        to[k] = ByteInfo{last_end,
                         kUnknownTime,
                         origin,
                         chunk_size,
                         errors != nullptr ? errors[i + k] : std::uint8_t{0},
                         false};
      }
      end_ += count;
      i = stretch_end;
    }
    for (; i < stretch_end; ++i) {
      Nanos end = 0;
      Nanos gap = kUnknownTime;
      time_byte(i, end, gap);
      store_byte(i, end, gap);
      last_end = end;
    }
    last_byte_end_ = last_end;
    if (buffered() >= kMaxPending) [[unlikely]] {
      decide(false);
    }
  }
  decide(false);
}

Nanos Framer::quiet_known_until(const Chunk& chunk) const {
  const Nanos first_start = chunk.t_first_start != kUnknownTime
                                ? chunk.t_first_start
                                : chunk.t_end - static_cast<Nanos>(chunk.bytes.size()) * char_time_;
  const Nanos unread_from = std::min(chunk.t_end, first_start + unread_reach());
  if (!chunk.read_late) return unread_from;
  return chunk.quiet_until == kUnknownTime ? kUnknownTime
                                           : std::min(unread_from, chunk.quiet_until);
}

void Framer::decide_after_silence() {
  decide(true);
  flush_noise();  // a silence ends a stretch of noise too
}

Nanos Framer::decidable_at() const {
  if ((buffered() == 0 && noise_.size == 0) || last_byte_end_ == kUnknownTime) {
    return kUnknownTime;
  }
  return last_byte_end_ + quiet_to_decide();
}

void Framer::finish() {
  decide(true);
  flush_noise();
}

void Framer::break_capture() {
  finish();
  last_byte_end_ = kUnknownTime;
  last_record_was_frame_ = false;
  glitch_since_frame_ = kUnknownTime;
  after_late_read_ = false;
  last_read_filled_ = false;
  expect_request();
}

void Framer::decide(bool at_end) {
  run_quiet_watch_on();
  while (buffered() > 0) {
    if (decide_head(at_end) == Verdict::kWait) break;
  }
}

bool Framer::boundary_at(std::size_t pos) const {
  return pos < buffered() && silence_before(info_at(pos).gap_before);
}

// Bytes [pos, pos + length) are one read, whole: the adapter handed them over apart from
// what came before and after. Adapters that deliver when the line goes idle (CH340, CP210x,
// PL2303) hand over a frame a read at a time, so where the timestamps cannot show the
// silence between frames, a read that begins and ends exactly where a CRC holds still shows
// it. One read, not several: an adapter that delivers on a timer cuts its reads anywhere, and
// among the ends of many reads one falls on a chance CRC zero far too often.
bool Framer::read_bounded(std::size_t pos, std::size_t length) const {
  const ByteInfo& first = info_at(pos);
  return first.read_start && first.chunk_size == length;
}

// At least t3.5 of silence beyond what the resolution may hide. The resolution is on the
// right so that an unknown gap (the smallest Nanos) fails the test without overflow.
bool Framer::contiguous_at(std::size_t pos) const {
  if (pos == 0 || pos >= buffered()) return false;
  const Nanos gap = info_at(pos).gap_before;
  // Less than half a character of silence, as far as the timestamps can tell: the start
  // bit followed the previous stop bit. No second sender turns its driver on that fast.
  return gap != kUnknownTime && gap + resolution_ < char_time_ / 2;
}

// Bytes [pos, end) start like a frame (plausible_start) that every length rule it may be
// read by, as a request or as a response, asks more bytes of.
bool Framer::starts_a_cut_frame(std::size_t pos, std::size_t end) const {
  if (!plausible_start(pos)) return false;
  const std::span<const std::uint8_t> view(bytes_.data() + begin_ + pos, end - pos);
  for (const Role role : {Role::kRequest, Role::kResponse}) {
    const Shape shape = predict_shape(view, role);
    const bool longer = shape.status == ShapeStatus::kNeedMore ||
                        (shape.status == ShapeStatus::kLength && shape.value > view.size());
    if (!longer && shape.status != ShapeStatus::kImpossible) return false;
  }
  return true;
}

// The first position in (0, length) after a pause that breaks t1.5; `length` where there is
// none.
std::size_t Framer::first_t15_silence(std::size_t length) const {
  for (std::size_t pos = 1; pos < length; ++pos) {
    if (breaks_t15(info_at(pos).gap_before)) return pos;
  }
  return length;
}

// At least half a character of silence before the byte at `pos`, beyond what the resolution
// may hide: the opposite of contiguous_at(), where the timestamps show either.
bool Framer::paused_before(std::size_t pos) const {
  if (pos == 0 || pos >= buffered()) return false;
  const Nanos gap = info_at(pos).gap_before;
  return gap != kUnknownTime && gap - resolution_ >= char_time_ / 2;
}

// Every start of the awaited answer after the head is looked at: noise may begin with its
// slave and function too.
bool Framer::awaited_answer_awaits_its_rest() const {
  if (!expect_response_) return false;
  const std::size_t n = buffered();
  for (std::size_t pos = 1; pos + 1 < n; ++pos) {
    if (awaited_response_at(pos) && predicted_length(pos) > n - pos) return true;
  }
  return false;
}

bool Framer::awaited_response_at(std::size_t pos) const {
  return expect_response_ && buffered() - pos >= 2 && byte_at(pos) == expected_slave_ &&
         (byte_at(pos + 1) & 0x7FU) == (expected_function_ & 0x7FU);
}

// Whether damaged bytes at `pos` still read as a frame: the answer the bus is waiting
// for, or a request-shaped frame of a slave and function the bus has seen. A response
// nobody asked for with a bad CRC is far more likely noise.
bool Framer::plausible_start(std::size_t pos) const {
  if (buffered() - pos < 2) return false;
  if (awaited_response_at(pos)) return true;
  const std::uint8_t slave = byte_at(pos);
  const std::uint8_t function = byte_at(pos + 1);
  if ((function & 0x80U) != 0 || !active_slaves_.test(slave)) return false;
  if (!is_public_function(function) && !is_user_defined_function(function)) return false;
  const std::span<const std::uint8_t> view(bytes_.data() + begin_ + pos, buffered() - pos);
  return predict_shape(view, Role::kRequest).status != ShapeStatus::kImpossible;
}

std::size_t Framer::predicted_length(std::size_t pos) const {
  const std::span<const std::uint8_t> view(bytes_.data() + begin_ + pos, buffered() - pos);
  const bool response_first = expect_response_ && view[0] == expected_slave_;
  const Role order[2] = {response_first ? Role::kResponse : Role::kRequest,
                         response_first ? Role::kRequest : Role::kResponse};
  for (const Role role : order) {
    const Shape shape = predict_shape(view, role);
    if (shape.status == ShapeStatus::kLength) return shape.value;
  }
  return 0;
}

// The CRC search from `pos`, extended over the bytes that came since it was last looked
// at: up to the first silence after its start (a frame ends at one), or its limit. On
// traffic that forms no frame (noise, unknown function codes) every byte is a start, and
// this is where the framer spends its time.
CrcScan& Framer::extended_scan(std::size_t pos) const {
  CrcScan& scan = crc_scans_.at(consumed_ + pos, resolution_);
  const std::size_t limit = std::min(buffered() - pos, kMaxAdu);
  if (scan.ended_at_silence || scan.scanned >= limit) return scan;
  const std::size_t scanned = scan.scanned;
  if (limit == scanned + 1 && scan.crc_known) {
    // One byte more: what per-byte reads bring to every open search at every byte.
    if (scanned > 0 && silence_before(info_at(pos + scanned).gap_before)) {
      scan.ended_at_silence = true;  // a frame ends at a silence
      return scan;
    }
    scan.crc = crc16_update(scan.crc, byte_at(pos + scanned));
    scan.scanned = static_cast<std::uint16_t>(limit);
    if (scan.crc == 0 && limit >= kMinAdu) scan.note_zero(limit);
    return scan;
  }
  if (limit - scanned >= kCrcStepsUpTo || !scan.crc_known) {
    extend_scan_otherwise(pos, scan, limit);
  } else {
    run_crc_on(pos, scan, limit);
  }
  return scan;
}

// The CRC run on over a few bytes more (per-byte reads bring one at a time), with the look
// for a silence in the same pass.
void Framer::run_crc_on(std::size_t pos, CrcScan& scan, std::size_t limit) const {
  const std::uint8_t* const bytes = bytes_.data() + begin_ + pos;
  const ByteInfo* const info = info_.data() + begin_ + pos;
  std::size_t scanned = scan.scanned;
  std::uint16_t crc = scan.crc;
  while (scanned < limit) {
    if (scanned > 0 && silence_before(info[scanned].gap_before)) {
      scan.ended_at_silence = true;  // a frame ends at a silence
      break;
    }
    crc = crc16_update(crc, bytes[scanned]);
    ++scanned;
    if (crc == 0 && scanned >= kMinAdu) scan.note_zero(scanned);
  }
  scan.crc = crc;
  scan.scanned = static_cast<std::uint16_t>(scanned);
}

// extended_scan() where the CRC does not simply run on. Over many bytes at once, the zeros
// are looked up by value (CrcZeroIndex), with no chain of CRC steps, and the CRC is not
// known from then on; a search so extended that then grows by a few bytes at a time gets
// its CRC back once, and runs on from there. Kept out of line: the one-byte steps of
// per-byte reads are the framer's hottest path, and this made them dearer inlined.
void Framer::extend_scan_otherwise(std::size_t pos, CrcScan& scan, std::size_t limit) const {
  if (limit - scan.scanned < kCrcStepsUpTo) {
    scan.crc = crc16({bytes_.data() + begin_ + pos, scan.scanned});
    scan.crc_known = true;
    run_crc_on(pos, scan, limit);
    return;
  }
  // The start's own first byte counts whatever silence comes before it.
  const std::size_t from = pos + std::max<std::size_t>(scan.scanned, 1);
  const std::size_t length = first_silence(from, pos + limit) - pos;
  crc_zeros_.note_zeros(scan, length, bytes_.data() + begin_, consumed_);
  scan.crc_known = false;
  scan.ended_at_silence = length < limit;
}

// The first window position in [from, to) with a silence before it, or `to`. The answer
// is kept: the searches from the starts of a stretch without silence ask about nearly the
// same positions one after the other, and looking at each again cost every search its
// whole length once more.
std::size_t Framer::first_silence(std::size_t from, std::size_t to) const {
  const std::uint64_t a = consumed_ + from;
  const std::uint64_t b = consumed_ + to;
  SilenceLook& kept = last_silence_look_;
  std::uint64_t look_from = a;
  if (kept.resolution == resolution_ && kept.from <= a && a <= kept.found) {
    // No silence in [kept.from, kept.found): none in [a, kept.found) either.
    if (kept.found < kept.to || b <= kept.found) return std::min(kept.found, b) - consumed_;
    look_from = kept.to;  // none up to kept.to: look on from there
  } else {
    kept.from = a;
  }
  const ByteInfo* const info = info_.data() + begin_;
  std::uint64_t p = look_from;
  while (p < b && !silence_before(info[p - consumed_].gap_before)) ++p;
  kept.to = b;
  kept.found = p;
  kept.resolution = resolution_;
  return p - consumed_;
}

bool Framer::crc_zero_follows(std::size_t pos, bool at_end, bool* pending) const {
  const CrcScan& scan = extended_scan(pos);
  if (scan.found_zero) return true;
  if (crc_search_may_go_on(scan, pos, at_end)) *pending = true;
  return false;
}

std::size_t Framer::generic_crc_length(std::size_t pos, bool at_end, int depth,
                                       bool* pending) const {
  const CrcScan& scan = extended_scan(pos);
  // Where the CRC holds, a frame ends if a silence or another frame follows; failing both,
  // where its read ends, if that is its first CRC zero (a frame's own end, where a frame
  // starts here) or only bytes 00 lie between the two (a CRC ending in 00 holds without that
  // byte too), and only once no longer length can still be confirmed by what follows it.
  std::size_t found = 0;
  std::size_t read_bounded_length = 0;
  std::size_t first_zero = 0;
  bool longer_may_confirm = false;
  // A span from a start inside a damaged frame comes out CRC-valid by chance where a real
  // frame ends, and holds the real frames between. Asked of the frame being decided only
  // (full depth), not of the links that vouch for it: a link is decided in turn, and asking
  // there too doubled the cost on such buses.
  const auto holds_frames = [&](std::size_t len) {
    return depth == kGenericDepth && holds_crc_chain({bytes_.data() + begin_ + pos, len});
  };
  // Only bytes 00 between the first CRC zero and `len` (a CRC ending in 00 holds without
  // them too, as appending 00 keeps a CRC valid).
  const auto only_zeros_after_first_zero = [&](std::size_t len) {
    const std::uint8_t* const at = bytes_.data() + begin_ + pos;
    return std::all_of(at + first_zero, at + len, [](std::uint8_t b) { return b == 0x00; });
  };
  const bool decided = scan.found_zero && scan.any_zero_length([&](std::size_t len) {
    const std::size_t next = pos + len;
    if (next == buffered()) {
      if (!at_end) {
        *pending = true;
        return true;
      }
      if (holds_frames(len)) return false;
      found = len;
      return true;
    }
    if (boundary_at(next)) {
      // Only bytes 00 between an earlier CRC zero and the silence, the first of them after
      // a pause the timestamps show: the frame ended at that zero, and the 00s are its
      // sender's turnaround (a frame's own bytes come back to back).
      const std::size_t end =
          first_zero != 0 && paused_before(pos + first_zero) && only_zeros_after_first_zero(len)
              ? first_zero
              : len;
      if (holds_frames(end)) return false;
      found = end;
      return true;
    }
    bool next_pending = false;
    // The last link of a chain (depth 1) is any CRC zero: kGenericDepth + 1 CRC-valid spans
    // back to back are no chance (a chance zero inside a frame is 1 in 65,536, and one from
    // there as well, about 1 in 260 for each further span). Without it, frames of no length
    // rule (vendor function codes) behind an adapter that hides every silence between them
    // were all noise.
    if (confirmed_length(next, at_end, depth - 1, &next_pending) > 0 ||
        (depth == 1 && crc_zero_follows(next, at_end, &next_pending))) {
      if (holds_frames(len)) return false;  // no frame of this length, nor one to wait for
      found = len;
      return true;
    }
    if (next_pending) {
      answer_may_change_ = true;  // the frame after may still come
      longer_may_confirm = true;
    }
    if (first_zero == 0) first_zero = len;
    if (read_bounded(pos, len) && only_zeros_after_first_zero(len)) {
      read_bounded_length = len;
    }
    return false;
  });
  if (decided) return found;
  if (read_bounded_length > 0 && !longer_may_confirm) return read_bounded_length;
  if (crc_search_may_go_on(scan, pos, at_end)) *pending = true;
  return 0;
}

std::size_t Framer::confirmed_length(std::size_t pos, bool at_end, int generic_depth, bool* pending,
                                     SearchNotes* notes) const {
  const std::size_t avail = buffered() - pos;
  const std::uint64_t start = consumed_ + pos;
  if (avail < kMinAdu) {
    if (!at_end) *pending = true;
    if (notes != nullptr) notes->until = std::min<std::uint64_t>(notes->until, start + kMinAdu);
    return 0;
  }
  const std::span<const std::uint8_t> view(bytes_.data() + begin_ + pos, avail);
  const bool response_first = expect_response_ && view[0] == expected_slave_;
  const Role order[2] = {response_first ? Role::kResponse : Role::kRequest,
                         response_first ? Role::kRequest : Role::kResponse};
  bool tried_generic = false;
  for (const Role role : order) {
    const Shape shape = predict_shape(view, role);
    switch (shape.status) {
      case ShapeStatus::kLength:
        if (shape.value > avail) {
          if (!at_end) *pending = true;
          if (notes != nullptr) notes->until = std::min(notes->until, start + shape.value);
          // The awaited answer still coming: a shorter reading as a request may only be
          // its first bytes (a CRC ending in 00 leaves the frame without its last byte
          // CRC-valid too), so wait for the answer's length before taking it.
          if (!at_end && response_first && role == Role::kResponse) return 0;
        } else if (shape.value >= kMinAdu && crc16(view.first(shape.value)) == 0) {
          return shape.value;
        }
        break;
      case ShapeStatus::kNeedMore:
        if (!at_end) *pending = true;
        if (notes != nullptr) notes->next_byte_matters = true;
        break;
      case ShapeStatus::kUnpredictable:
        if (generic_depth > 0 && !tried_generic) {
          tried_generic = true;
          const std::size_t len = generic_crc_length(pos, at_end, generic_depth, pending);
          if (len > 0) return len;
          if (notes != nullptr) note_crc_scan(pos, *notes);
        }
        break;
      case ShapeStatus::kImpossible: break;
    }
  }
  // A frame whose byte count lies (e.g. a vendor's FC10 with 13 data bytes under a count
  // of 12) fits no length rule, yet its CRC holds up to a silence or to the next frame.
  if (generic_depth > 0 && !tried_generic && !*pending) {
    bool more_may_confirm = false;
    const std::size_t length = generic_crc_length(pos, at_end, generic_depth, &more_may_confirm);
    if (more_may_confirm) answer_may_change_ = true;
    if (length == 0 && notes != nullptr) note_crc_scan(pos, *notes);
    return length;
  }
  return 0;
}

// The CRC search from `pos` after a search at full depth found no frame there: one that
// found CRC zeros waits on what follows them, which any byte may change; one that found
// none changes only at a zero, a silence, or the longest frame.
void Framer::note_crc_scan(std::size_t pos, SearchNotes& notes) const {
  const std::uint64_t start = consumed_ + pos;
  const CrcScan& scan = crc_scans_.at(start, resolution_);
  if (scan.found_zero) {
    notes.next_byte_matters = true;
    return;
  }
  notes.watch_crc_scan = true;
  notes.until = std::min<std::uint64_t>(notes.until, start + kMaxAdu);
}

// run_quiet_watch_on() where starts are watched: they run on over a read's bytes, else
// (more than a packet's) the watches end.
void Framer::run_quiet_watch_on_to(std::uint64_t end) {
  const std::uint64_t through = quiet_starts_.watched_through();
  if (through < consumed_ || end - through >= kWatchedReadsUpTo) {
    quiet_starts_.unwatch_all(end);
    return;
  }
  const std::size_t from = through - consumed_;
  for (std::size_t pos = from; pos < buffered(); ++pos) {
    if (silence_before(info_at(pos).gap_before)) {
      quiet_starts_.unwatch_all(end);  // a frame may end at it
      return;
    }
  }
  if (quiet_starts_.any_crc_watched()) {
    crc_zeros_.compute_through(end, bytes_.data() + begin_, consumed_);
  }
  quiet_starts_.run_on(crc_zeros_, end);
  // A start whose CRC search reached the longest frame with no zero, watched for that
  // alone, is known to start no frame: its next search would say so and settle it.
  quiet_starts_.take_exhausted(epoch_,
                               [this](std::uint64_t start) { settled_.set(start % kWindow); });
}

// Whether the CRC search from `pos`, extended over the bytes that came since, still found
// no zero and no silence (as note_crc_scan() required).
bool Framer::crc_scan_still_quiet(std::size_t pos) const {
  const CrcScan& scan = extended_scan(pos);
  return !scan.ended_at_silence && !scan.found_zero;
}

std::size_t Framer::quiet_crc_steps(const std::uint8_t* bytes, std::size_t count) const {
  const CrcScan* const scan = crc_scans_.find(consumed_, resolution_);
  if (scan == nullptr || !scan->crc_known || scan->found_zero || scan->ended_at_silence ||
      scan->scanned != buffered()) {
    return 0;
  }
  return scan->steps_without_zero(bytes, count);
}

void Framer::run_crc_steps(const std::uint8_t* bytes, std::size_t count) const {
  crc_scans_.at(consumed_, resolution_).run_on(bytes, count);
}

// The start at `pos`, remembered as `quiet` and found still quiet, is watched from here on
// where it waits on no CRC search, or its search covers the window up to its end (the
// watch takes it on from there, see quiet_starts.hpp).
void Framer::watch(std::size_t pos, const QuietStart& quiet) {
  if (!quiet.watch_crc_scan) {
    quiet_starts_.watch(quiet, crc_zeros_);
    return;
  }
  const CrcScan* scan = crc_scans_.find(quiet.start, resolution_);
  if (scan != nullptr && scan->scanned == buffered() - pos) {
    crc_zeros_.compute_through(consumed_ + buffered(), bytes_.data() + begin_, consumed_);
    quiet_starts_.watch(quiet, crc_zeros_);
  }
}

std::size_t Framer::settled_or_confirmed_length(std::size_t pos, bool at_end, bool* pending) {
  const std::uint64_t start = consumed_ + pos;
  const std::size_t slot = start % kWindow;
  if (settled_.test(slot)) return 0;
  if (!at_end) {
    const QuietStart* quiet = quiet_starts_.find(start, epoch_, consumed_ + buffered());
    if (quiet != nullptr && (!quiet->watch_crc_scan || crc_scan_still_quiet(pos))) {
      if (watchable(pos)) watch(pos, *quiet);
      *pending = quiet->pending;
      answer_may_change_ = quiet->may_change;
      return 0;
    }
  }
  quiet_starts_.unwatch(start);
  answer_may_change_ = false;
  SearchNotes notes;
  const std::size_t length = confirmed_length(pos, at_end, kGenericDepth, pending, &notes);
  // Only a search that waited for nothing is final: at the end of input, too few bytes
  // are a "no" that more bytes could turn into a "yes".
  if (length == 0 && !*pending && !answer_may_change_ && !at_end) settled_.set(slot);
  if (length == 0 && (*pending || answer_may_change_) && !at_end && !notes.next_byte_matters &&
      config_.remember_quiet_starts) {
    const QuietStart& quiet = quiet_starts_.remember(
        start, epoch_, notes.until, notes.watch_crc_scan, *pending, answer_may_change_);
    // Watched from here on, as on its next ask would have it (the answer is the same):
    // asking again first cost each start of a stretch of noise a second look-up of its CRC
    // search. Not a start that waits for bytes in a short window (a frame coming in on a
    // healthy bus): a watch there would keep push_if_head_waits() from taking the next
    // bytes, up to the start's predicted end.
    if (watchable(pos) && (buffered() >= kWatchedStretch || !*pending) &&
        notes.until > consumed_ + buffered())
      watch(pos, quiet);
  }
  return length;
}

Framer::Verdict Framer::decide_head(bool at_end) {
  const std::size_t n = buffered();
  const bool forced = at_end || n >= kMaxPending;

  bool head_pending = false;
  const std::size_t head_len = settled_or_confirmed_length(0, at_end, &head_pending);
  if (head_len > 0) {
    emit_frame(head_len, true);  // confirmed lengths are CRC-valid ones
    return Verdict::kEmitted;
  }

  if (head_pending && !forced) {
    // The head may still become a frame. Give up on it early only where a silence the
    // timestamps show is followed by a frame the CRC confirms.
    // Positions already found silent-free need no second look.
    std::size_t p = 1;
    if (silence_search_from_ > consumed_ + 1) p = silence_search_from_ - consumed_;
    bool all_silent_free = true;
    for (; p < n; ++p) {
      if (!boundary_at(p)) {
        if (all_silent_free) silence_search_from_ = consumed_ + p + 1;
        continue;
      }
      all_silent_free = false;
      bool pending = false;
      if (confirmed_length(p, at_end, kGenericDepth, &pending) > 0) {
        classify_span(first_whole_frame_before(p));
        return Verdict::kEmitted;
      }
    }
    // Every position after the head is now known silent-free, also where there is none
    // yet (the head alone, a frame's first byte): so the next byte may be taken by
    // push_if_head_waits(), which asks exactly that.
    if (all_silent_free && silence_search_from_ < consumed_ + n) {
      silence_search_from_ = consumed_ + n;
    }
    return Verdict::kWait;
  }

  // Nothing at the head can be a valid frame: find where the next one starts.
  std::size_t first_pending = 0;
  // Starts this loop watches come before the one it looks at: with none watched at first,
  // there is none to ask about.
  const bool any_watched = !at_end && quiet_starts_.any_watched(epoch_);
  for (std::size_t p = std::max<std::size_t>(1, scan_resume_); p < n; ++p) {
    if (any_watched) {
      // Watched starts answer as they did: nothing yet (see quiet_starts.hpp).
      std::uint64_t watched_pending = QuietStarts::kNone;
      p = static_cast<std::size_t>(
          quiet_starts_.skip_watched(consumed_ + p, consumed_ + n, watched_pending) - consumed_);
      if (first_pending == 0 && watched_pending != QuietStarts::kNone) {
        first_pending = static_cast<std::size_t>(watched_pending - consumed_);
      }
      if (p == n) break;
    }
    if (!at_end && n - p < kMinAdu) {
      // Too few bytes for any frame, here and at every start after it: each search would
      // only say "wait" (confirmed_length()). Per-byte reads of bytes that form nothing
      // asked that of the last three starts at every byte.
      if (first_pending == 0) first_pending = p;
      break;
    }
    bool pending = false;
    if (settled_or_confirmed_length(p, at_end, &pending) > 0) {
      scan_resume_ = 1;
      classify_span(p);
      return Verdict::kEmitted;
    }
    if (pending && first_pending == 0) first_pending = p;
  }
  scan_resume_ = first_pending == 0 ? n : first_pending;

  // No confirmed frame ahead. A silence the timestamps show still delimits a frame.
  // Positions already found silent-free need no second look (on per-byte reads of bytes
  // that form nothing, this is asked at every byte).
  std::size_t p = 1;
  if (silence_search_from_ > consumed_ + 1) p = silence_search_from_ - consumed_;
  for (; p < n; ++p) {
    if (boundary_at(p)) {
      silence_search_from_ = consumed_ + p;
      scan_resume_ = 1;
      classify_span(p);
      return Verdict::kEmitted;
    }
  }
  silence_search_from_ = consumed_ + n;
  if (!forced) return Verdict::kWait;
  scan_resume_ = 1;
  if (at_end) {
    classify_span(n);
  } else {
    // Window full of bytes that form nothing: release those that cannot start a frame.
    emit_noise(std::max<std::size_t>(1, first_pending == 0 ? n - kMaxAdu : first_pending));
  }
  return Verdict::kEmitted;
}

// The head waited for a length that a silence at `end` cut short (noise whose bytes read
// as a byte count, a damaged one): whole frames may have come between the two, each in
// bytes the head waited for. The first start in (0, end) of a frame the CRC confirms that
// ends by `end`; `end` where there is none.
std::size_t Framer::first_whole_frame_before(std::size_t end) const {
  for (std::size_t q = 1; q + kMinAdu <= end; ++q) {
    if (settled_.test((consumed_ + q) % kWindow)) continue;  // known to start no frame
    bool pending = false;
    const std::size_t length = confirmed_length(q, false, kGenericDepth, &pending);
    if (length > 0 && q + length <= end) return q;
  }
  return end;
}

// Bytes [0, length) precede a confirmed frame, a silence, or the end: a damaged frame
// when they start like one the bus has seen (known slave and function), else noise.
void Framer::classify_span(std::size_t length) {
  // A fragment of the awaited answer is a truncated frame even when very short.
  const std::size_t min_frame = awaited_response_at(0) ? 3 : kMinAdu;
  const bool frame_like = length >= min_frame && plausible_start(0);
  if (frame_like) {
    // A CRC-valid prefix is a whole frame (one with no length rule, e.g. FC08/00), and
    // what follows it is the next record.
    std::uint16_t crc = kCrcInit;
    for (std::size_t len = 1; len < length && len <= kMaxAdu; ++len) {
      crc = crc16_update(crc, byte_at(len - 1));
      if (len >= kMinAdu && crc == 0) {
        emit_frame(len, true);
        return;
      }
    }
  }
  // No frame holds here, and the timestamps show the line silent for longer than t1.5
  // inside: a sender stopped there (a glitch, then a frame; a frame cut short, then noise).
  // That part is a record of its own, and what follows the silence is decided afresh;
  // unless the frame's length rule says it goes on past the silence (a slow sender's pause
  // inside its frame, the frame then damaged or cut short). A read addressed to 0 has no
  // rule that holds: a broadcast only writes, so that 0x00 is a glitch before a pause.
  const std::size_t predicted = frame_like ? predicted_length(0) : 0;
  const bool broadcast_read = length >= 2 && byte_at(0) == 0 && !may_be_broadcast(byte_at(1));
  if (const std::size_t cut = first_t15_silence(length);
      cut < length && (predicted <= cut || broadcast_read)) {
    classify_span(cut);
    return;
  }
  if (frame_like) {
    // A frame with a bad CRC, then more bytes; but never a cut where the timestamps show
    // the line was not silent: those bytes came from one sender in one go. Nor where what
    // would follow the cut is the start of a frame that the span's end cuts short: a
    // damaged function code whose length rule is shorter than the frame leaves that too,
    // and two broken records where one was sent.
    if (predicted >= kMinAdu && predicted < length && !contiguous_at(predicted) &&
        !starts_a_cut_frame(predicted, length)) {
      emit_frame(predicted);
      return;
    }
    if (length <= kMaxAdu) {
      emit_frame(length);  // bad CRC, truncated, or an unknown length
      return;
    }
  }
  emit_noise(length);
}

Nanos Framer::fill_record(Record& rec, std::size_t from, std::size_t length) const {
  const ByteInfo& first = info_at(from);
  rec.t_start = first.t_end - char_time_;
  rec.t_end = info_at(from + length - 1).t_end;
  rec.gap_before = first.gap_before;
  rec.origin = first.origin;
  rec.size = static_cast<std::uint16_t>(length);
  std::memcpy(rec.storage.data(), bytes_.data() + begin_ + from, length);
  std::uint8_t errors = first.errors;
  // kUnknownTime, the least Nanos, never wins against a measured gap.
  Nanos longest_inner_gap = kUnknownTime;
  for (std::size_t i = 1; i < length; ++i) {
    const ByteInfo& b = info_at(from + i);
    errors |= b.errors;
    longest_inner_gap = std::max(longest_inner_gap, b.gap_before);
  }
  rec.line_errors = errors;
  return longest_inner_gap;
}

void Framer::emit_frame(std::size_t length, bool crc_confirmed) {
  flush_noise();
  Record& rec = scratch_;
  rec.reset_keeping_storage();
  rec.kind = RecordKind::kFrame;
  const Nanos longest_inner_gap = fill_record(rec, 0, length);
  classify_frame(rec, crc_confirmed);

  // Timing, only where the timestamps can show it. The longest silence inside the frame
  // decides both what it teaches and whether it breaks t1.5.
  if (rec.crc_ok && longest_inner_gap > resolution_) learn_from(rec);
  const Nanos res = resolution_;
  if (breaks_t15(longest_inner_gap)) {
    rec.issues.add(IssueId::kT15);
  }
  // Silence since the previous frame; a turnaround glitch between them does not hide it.
  Nanos silence = kUnknownTime;
  if (last_record_was_frame_) silence = rec.gap_before;
  if (glitch_since_frame_ != kUnknownTime && rec.gap_before != kUnknownTime) {
    silence = glitch_since_frame_ + rec.gap_before;
  }
  if (silence != kUnknownTime && silence + res < t3_5_) rec.issues.add(IssueId::kT35);
  glitch_since_frame_ = kUnknownTime;
  if ((rec.line_errors & (kParityError | kFramingError)) != 0) rec.issues.add(IssueId::kLineError);
  if ((rec.line_errors & kBreak) != 0) rec.issues.add(IssueId::kBreak);
  if ((rec.line_errors & kOverrun) != 0) rec.issues.add(IssueId::kOverrun);

  rec.seq = next_seq_++;
  if (rec.crc_ok) active_slaves_.set(rec.slave());

  // Track what comes next: after a request, its response (echo functions alternate).
  const std::uint8_t slave = rec.slave();
  const std::uint8_t function = rec.function();
  if (rec.crc_ok) {
    const bool fits_request = (rec.shape_fit & kFitsRequest) != 0;
    const bool fits_response = (rec.shape_fit & kFitsResponse) != 0;
    const bool awaited = expect_response_ && slave == expected_slave_ &&
                         (function & 0x7FU) == (expected_function_ & 0x7FU);
    if (rec.is_exception() || (awaited && (fits_response || !fits_request))) {
      expect_request();  // that was the awaited response
    } else if ((fits_request || !fits_response) && slave != 0) {
      expect_response_from(slave, function);  // a request (echo functions: the first)
    } else {
      expect_request();
    }
  }

  last_record_end_ = rec.t_end;
  last_record_was_frame_ = true;
  consume(length);
  out_.on_record(rec);
}

bool Framer::reads_are_batched() const {
  // Up to 2% of reads with several bytes still leave byte timing observable almost
  // everywhere (a per-byte source whose reader fell behind now and then).
  return batched_chunks_ * 50 > chunks_;
}

// A CRC-valid frame was sent without a pause inside (a pause that long would break it
// for every strict receiver), so a silence its timestamps show between two reads, where
// the reads are batched, is how late the adapter delivered: the timestamps cannot resolve
// anything shorter. Learned before the frame's own checks, so a USB packet boundary
// inside a frame is never reported as a t1.5 violation. A per-byte source never teaches
// this: there a pause inside a frame is a real one.
//
// Only a frame whose length its function code foretells teaches. One with no length rule
// may be a chance CRC zero over several frames: the silences between them, taken for an
// adapter's delay, raised the resolution, which hid more silences, which let the next chance
// zero through, until frames with no length rule (they end at silences) were found no more.
// The price: on a bus of such frames alone, a read that came later than the resolution
// inside one of them is a t1.5 issue.
//
// Nor does the first frame of a slave: a chance CRC zero that straddles the silence between
// two frames (the last byte of one, a few of the next) names a slave the bus has not shown,
// and that silence, taught as delay, hid every later one on a bus of vendor function codes.
void Framer::learn_from(const Record& frame) {
  if (!config_.learn_resolution || config_.per_byte_exact || !reads_are_batched() ||
      frame.shape_fit == kFitsNone || !active_slaves_.test(frame.slave())) {
    return;
  }
  for (std::size_t i = 1; i < frame.size; ++i) {
    const ByteInfo& b = info_at(i);
    if (b.gap_before == kUnknownTime || b.gap_before <= resolution_) continue;
    if (b.chunk_size < 2 && info_at(i - 1).chunk_size < 2) continue;
    resolution_ = b.gap_before;
    silence_search_from_ = 0;  // silences are judged anew with it
    settled_.clear_all();
    new_epoch();
  }
}

void Framer::emit_noise(std::size_t length) {
  // Noise on both sides of a silence the timestamps show is two stretches, not one.
  if (noise_.size > 0 && boundary_at(0)) flush_noise();
  std::size_t done = 0;
  while (done < length) {
    if (noise_.size == kMaxAdu) flush_noise();
    const std::size_t take = std::min(length - done, kMaxAdu - noise_.size);
    if (noise_.size == 0) {
      fill_record(noise_, done, take);
    } else {
      std::memcpy(noise_.storage.data() + noise_.size, bytes_.data() + begin_ + done, take);
      noise_.size = static_cast<std::uint16_t>(noise_.size + take);
      noise_.t_end = info_at(done + take - 1).t_end;
      for (std::size_t i = 0; i < take; ++i) noise_.line_errors |= info_at(done + i).errors;
    }
    done += take;
  }
  consume(length);
}

void Framer::flush_noise() {
  if (noise_.size == 0) return;
  noise_.kind = RecordKind::kNoise;
  noise_.seq = next_seq_++;
  noise_.crc_ok = false;
  noise_.issues = IssueSet{};
  noise_.issues.add(IssueId::kNoiseBytes);
  if ((noise_.line_errors & (kParityError | kFramingError)) != 0) {
    noise_.issues.add(IssueId::kLineError);
  }
  if ((noise_.line_errors & kBreak) != 0) noise_.issues.add(IssueId::kBreak);
  if ((noise_.line_errors & kOverrun) != 0) noise_.issues.add(IssueId::kOverrun);
  glitch_since_frame_ = kUnknownTime;
  if (is_turnaround_glitch(noise_)) {
    noise_.issues.add(IssueId::kTurnaroundGlitch);
    glitch_since_frame_ = noise_.t_end - last_record_end_;
  }
  last_record_end_ = noise_.t_end;
  last_record_was_frame_ = false;
  // The record leaves from scratch, so that while the sink handles it the framer holds no
  // trace of it (oldest_pending_start() is asked meanwhile when ports are merged).
  noise_out_ = noise_;
  noise_ = Record{};
  noise_.kind = RecordKind::kNoise;
  out_.on_record(noise_out_);
}

// A lone byte at most about a character after a frame's end, as the timestamps show: the
// frame's sender releasing the line (its RS-485 driver switching off, or a transceiver
// without fail-safe bias reading the idle line as a start bit). Any value can come out.
bool Framer::is_turnaround_glitch(const Record& noise) const {
  return noise.size == 1 && last_record_was_frame_ && noise.gap_before != kUnknownTime &&
         noise.gap_before <= char_time_ + char_time_ / 2;
}

void Framer::consume(std::size_t length) {
  quiet_starts_.unwatch_range(consumed_, length);
  begin_ += length;
  consumed_ += length;
  if (begin_ == end_) begin_ = end_ = 0;
  scan_resume_ = scan_resume_ > length ? scan_resume_ - length : 1;
}

}  // namespace rtu

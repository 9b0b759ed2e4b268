#pragma once
// The frame splitter: turns timed chunks into frames and noise records.
//
// Two kinds of evidence, used together:
//  * Silences between bytes, where the timestamps can show them. A chunk's bytes are
//    placed by counting back from its read time at the line rate, so only silences at
//    chunk boundaries are seen at all, and only to within the capture's timing resolution.
//  * What a frame's function code allows: the expected length in either role (request or
//    response, byte-count fields included), confirmed by the CRC. This is what survives
//    USB adapters that batch bytes into 16 ms transfers and glue requests to responses.
//    A function code with no length rule (a vendor's) has only its CRC: such a frame ends
//    where the CRC holds and a silence or a confirmed frame follows, or, where no silence
//    shows, where a short chain of CRC-valid spans continues back to back behind it.
//
// A CRC-confirmed length-predicted frame always wins (it may even span a silence: that is
// a `t1.5` issue on the frame). When nothing at the head of the buffer is confirmed, the
// framer looks for the next position where a confirmed frame starts and classifies the
// bytes before it as a damaged frame (bad CRC, truncated) or, when they cannot be one,
// as noise. Bytes are never dropped: each ends up in exactly one record.
//
// Memory is fixed: a bounded byte window; nothing allocates per byte.
#include <algorithm>
#include <array>
#include <bitset>
#include <cstdint>

#include "core/chunk.hpp"
#include "framing/crc_scan_cache.hpp"
#include "framing/crc_zero_index.hpp"
#include "framing/quiet_starts.hpp"
#include "framing/record.hpp"
#include "framing/window_bits.hpp"
#include "serial/line_settings.hpp"

namespace rtu {

struct FramerConfig {
  LineSettings line;
  // Silences shorter than this cannot be seen in the timestamps (see TimingEstimator):
  // the starting value, raised as the chunks show more (see Framer::learn_from).
  Nanos resolution = 0;
  // Chunks carry exact per-byte start times (logic analyser exports).
  bool per_byte_exact = false;
  // Whether the resolution may be raised from what the chunks show (off when the user
  // fixed it, and for exact per-byte timestamps).
  bool learn_resolution = true;
  // Whether searches that said "not yet" are remembered (see quiet_starts.hpp). Only a
  // test turns it off, to check that remembering changes no record.
  bool remember_quiet_starts = true;
};

// How long the framer waits, past t3.5, for more bytes of a frame that is not complete
// yet before it decides without them. A USB adapter holds bytes for up to its latency
// timer (16 ms by default on FTDI, a few ms on CH340/CP210x/PL2303), so the rest of a
// frame can come that much later even on a healthy line; giving up earlier turns a whole
// frame into a truncated one plus noise. It only delays the decision, never a timestamp.
inline constexpr Nanos kDeliveryPatience = 20 * kNanosPerMilli;
// Reads smaller than this never count as a full packet (quiet_to_decide()): per-byte and
// few-byte reads say nothing of an adapter's buffer.
inline constexpr std::size_t kFullReadAtLeast = 8;

class Framer {
 public:
  // `out` receives every record, in time order. It must outlive the framer.
  Framer(const FramerConfig& config, RecordSink& out);

  // A read: first advance(quiet_known_until(chunk)) (nothing was read before it), then its
  // bytes.
  void push(const Chunk& chunk) {
    if (chunk.bytes.size() == 1 && ByteReads::holds(chunk) && !after_late_read_ &&
        push_if_head_waits(chunk.bytes[0], chunk.t_end, chunk.origin)) {
      return;
    }
    push_without_shortcut(chunk);
  }
  // No read completed before `now`. Once that is t3.5 plus the resolution (at least
  // kDeliveryPatience; see quiet_to_decide()) after the last byte, what is buffered is
  // decided as complete.
  // push() calls it with each read's time, and a live capture calls it while the line is
  // quiet: both reach the same decision at the same point of the byte stream, so a live
  // run and the replay of its recording give the same records.
  void advance(Nanos now) {
    // Asked at every read, and nearly always too soon: that answer inline, and before asking
    // whether a frame's rest is held (a look over the window), which only lengthens the wait.
    if ((buffered() == 0 && noise_.size == 0) || last_byte_end_ == kUnknownTime) return;
    const Nanos quiet = now - last_byte_end_;
    if (quiet < t3_5_ + delivery_allowance() || quiet < quiet_to_decide()) return;
    decide_after_silence();
  }
  // push() of a one-byte read (one ByteReads::holds: `byte`, completed at `t_end`) that
  // brings the head of the window no nearer a decision, where that is known without a
  // search: then it does what push() would (store the byte, see below) and returns true,
  // and no record comes out. Otherwise it changes nothing and returns false. Inline: asked
  // at every read of a per-byte capture.
  bool push_if_head_waits(std::uint8_t byte, Nanos t_end, std::uint64_t origin);
  // push_if_head_waits() for the reads of `reads` from `first` on, one after the other, as
  // long as it would say true: returns how many it took, and when it took any, sets `latest`
  // to the latest completion time among them. Asked once for a run of such reads, not at
  // every read. The read after them, if any, is one it would say false for.
  std::size_t push_reads_while_head_waits(const ByteReads& reads, std::size_t first, Nanos& latest);
  // push() for a caller that has just seen push_if_head_waits() say false for the read.
  void push_without_shortcut(const Chunk& chunk);
  // End of input: everything still buffered is emitted.
  void finish();
  // finish(), and the input goes on after an unknown time: the next byte shows no silence
  // before it, and no frame is expected from what came before (a recorder started again).
  void break_capture();

  // Expected next frame, from the framer's own reading of the bus (after a request, its
  // response); used only to break ties between equally valid readings.
  void expect_response_from(std::uint8_t slave, std::uint8_t function);
  void expect_request();

  // The timing resolution in force now (the configured one, raised by what was learned).
  [[nodiscard]] Nanos resolution() const { return resolution_; }
  // Start of the oldest byte not yet emitted in a record, kUnknownTime when none: records
  // still to come can start no earlier.
  [[nodiscard]] Nanos oldest_pending_start() const {  // inline: asked at every read
    if (noise_.size > 0) return noise_.t_start;
    if (buffered() > 0) return info_at(0).t_end - char_time_;
    return kUnknownTime;
  }
  // Earliest start of a byte not yet read when nothing was read up to `now`: an adapter
  // may still hold bytes for its delivery delay (the resolution, at least
  // kDeliveryPatience), and one more may be on the wire.
  [[nodiscard]] Nanos earliest_unread_start(Nanos now) const { return now - unread_reach(); }
  // How far before a moment of quiet unread bytes may have started (see above).
  [[nodiscard]] Nanos unread_reach() const { return delivery_allowance() + char_time_; }
  // The latest moment before `chunk` that the line is known to have been quiet, as far as
  // unread bytes go (what advance() may be told before its bytes): no later than its first
  // byte could still have been unread, which for a read of more bytes than an adapter's
  // delivery delay spans lies before its end (deciding at its end would end a frame the
  // read goes on with); no later than the port was seen empty before a late read, and
  // kUnknownTime for a late read where that is not known.
  [[nodiscard]] Nanos quiet_known_until(const Chunk& chunk) const;
  // The moment from which advance() decides the bytes held now (the line quiet for t3.5
  // beyond what an adapter may hold back); kUnknownTime when none are held.
  [[nodiscard]] Nanos decidable_at() const;

 private:
  static constexpr std::size_t kWindow = 2048;             // bytes held while deciding
  static constexpr std::size_t kMaxPending = 4 * kMaxAdu;  // forces a decision beyond this
  static_assert(kWindow < CrcZeroIndex::kReach);
  // A CRC search extended by fewer bytes than this runs the CRC on over them; by more, it
  // looks its zeros up (CrcZeroIndex).
  static constexpr std::size_t kCrcStepsUpTo = 4;
  // Waiting starts are watched (see quiet_starts.hpp) across reads of fewer bytes than
  // kCrcStepsUpTo, and across those of fewer than kWatchedReadsUpTo (a USB adapter's
  // packet) where the window already holds kWatchedStretch bytes or more: a stretch that
  // forms nothing (noise, a line read at the wrong baud rate), whose hundreds of starts
  // wait read after read. A watch costs a compare per watched start and byte, eight at a
  // time; answering a start again costs a look-up of its CRC search, some 300
  // instructions. Where frames follow each other, a read's starts are decided with the
  // next read, and watching them cost random frames read a frame at a time 4%.
  static constexpr std::size_t kWatchedReadsUpTo = 64;
  static constexpr std::size_t kWatchedStretch = kMaxAdu;

  struct ByteInfo {
    Nanos t_end = 0;
    Nanos gap_before = kUnknownTime;  // observable silence before this byte
    std::uint64_t origin = 0;
    std::uint16_t chunk_size = 0;  // bytes in the read this byte came in
    std::uint8_t errors = 0;
    bool read_start = false;  // the first byte of its read
  };

  enum class Verdict : std::uint8_t { kEmitted, kWait };

  // A byte's end and the silence before it, for a byte that ended no earlier than
  // `earliest_end` (what its read's timing says) and no earlier than one character time after
  // the byte before it, which ended at `previous_end` (known). The shortcuts time a one-byte
  // read with it, as push() times each byte of a read (push() keeps its own two lines: there
  // only a read's first byte needs the silence, and computing it for every byte cost
  // 0.2% of a USB-chunked decode).
  struct ByteTiming {
    Nanos end = 0;
    Nanos gap = 0;
  };
  static ByteTiming time_after(Nanos earliest_end, Nanos previous_end, Nanos char_time) {
    const Nanos end = std::max(earliest_end, previous_end + char_time);
    return {end, end - char_time - previous_end};
  }

  // How long an adapter may hold bytes back (the resolution, at least kDeliveryPatience),
  // and the quiet after the last byte that decides what is held: t3.5 beyond that.
  [[nodiscard]] Nanos delivery_allowance() const {
    return std::max(resolution_, kDeliveryPatience);
  }
  // Twice that for a head whose rest is still to come (head_awaits_its_rest()), after a read
  // as large as any the adapter has given: such a read shows a full packet, sent because the
  // adapter's buffer filled rather than because the line went idle, so the rest may wait
  // for the next idle line, after further frames (an adapter that sends when the line has
  // been idle, on a bus polled faster than its idle wait). Only then: elsewhere the quiet
  // after a read is what shows that a frame of no length rule ended (random traffic lost
  // 1.8% of its frames when every head waited twice as long).
  [[nodiscard]] Nanos quiet_to_decide() const {
    const bool rest_held = last_read_filled_ && head_awaits_its_rest();
    return t3_5_ + (rest_held ? 2 : 1) * delivery_allowance();
  }
  // Whether the head is no frame yet and may still become one with more bytes: its length
  // rule says so, or, with none, its CRC search (where one was made) found no zero and may
  // run on (no silence ended it, and it is shorter than the longest frame). Or the head is
  // noise and the awaited answer after it awaits its rest.
  [[nodiscard]] bool head_awaits_its_rest() const {
    if (buffered() == 0) return false;
    const std::size_t predicted = predicted_length(0);
    if (predicted > buffered()) return true;
    if (predicted == 0) {
      const CrcScan* scan = crc_scans_.find(consumed_, resolution_);
      if (scan != nullptr && !scan->found_zero && !scan->ended_at_silence &&
          scan->scanned < kMaxAdu) {
        return true;
      }
    }
    return awaited_answer_awaits_its_rest();  // a look over the window: asked last
  }
  // The answer the bus awaits starts after bytes that are no frame (noise before it), and
  // its length rule says more of it is still to come.
  [[nodiscard]] bool awaited_answer_awaits_its_rest() const;
  void decide_after_silence();  // advance() once the line was quiet long enough
  bool push_first_byte_if_it_waits(std::uint8_t byte, Nanos now, std::uint64_t origin);
  std::size_t push_reads_to_waiting_head(const std::uint8_t* bytes, const Nanos* t_ends,
                                         std::uint64_t origin, std::size_t count, Nanos& latest);
  void slide_window();
  // `frame`: the frame being emitted, still at the window's head.
  void learn_from(const Record& frame);
  [[nodiscard]] bool reads_are_batched() const;
  void decide(bool at_end);
  Verdict decide_head(bool at_end);

  // Length of a CRC-confirmed frame starting at `pos` (0 if none can be confirmed with
  // the bytes buffered now). `pending` is set when a predicted length needs more bytes.
  // `generic_depth` > 0 also accepts frames with no length rule, confirmed by their CRC and
  // by what follows them (a silence, or a further confirmed frame, up to that depth).
  // `notes`, at full depth only: what alone can change a "not yet" (see quiet_starts.hpp).
  std::size_t confirmed_length(std::size_t pos, bool at_end, int generic_depth, bool* pending,
                               SearchNotes* notes = nullptr) const;
  void note_crc_scan(std::size_t pos, SearchNotes& notes) const;
  bool crc_scan_still_quiet(std::size_t pos) const;
  // For push_reads_to_waiting_head(), where the head waits on its CRC search: how many of
  // the next `count` bytes keep it quiet (0 if the search cannot be run on, as where it does
  // not cover the window)...
  [[gnu::noinline]] std::size_t quiet_crc_steps(const std::uint8_t* bytes, std::size_t count) const;
  // ... and the search run on over the `count` bytes then taken.
  [[gnu::noinline]] void run_crc_steps(const std::uint8_t* bytes, std::size_t count) const;
  [[gnu::noinline]] void watch(std::size_t pos, const QuietStart& quiet);
  // Whether a quiet start at `pos` is worth watching (see quiet_starts.hpp): while reads
  // are watched (kWatchedReadsUpTo; a longer one ends every watch), and not the head, whose
  // answer decide_head() asks for apart.
  [[nodiscard]] bool watchable(std::size_t pos) const {
    return pos > 0 && watching_reads_ && quiet_starts_.watched_through() == consumed_ + buffered();
  }
  // The watches of quiet_starts_ brought up to the window end. Asked at every decision:
  // where nothing is watched (nearly always, on traffic that forms frames), that inline.
  void run_quiet_watch_on() {
    const std::uint64_t end = consumed_ + buffered();
    if (quiet_starts_.watched_through() == end) return;
    if (quiet_starts_.any_watched()) {
      run_quiet_watch_on_to(end);
    } else {
      quiet_starts_.unwatch_all(end);
    }
  }
  void run_quiet_watch_on_to(std::uint64_t end);
  void new_epoch() { ++epoch_; }  // ends the watches too (see QuietStarts::any_watched)
  // confirmed_length() at full depth, skipping positions already known to be no start.
  std::size_t settled_or_confirmed_length(std::size_t pos, bool at_end, bool* pending);
  std::size_t generic_crc_length(std::size_t pos, bool at_end, int depth, bool* pending) const;
  // Whether the CRC search from `pos` meets a zero (a frame's worth of bytes or more) before
  // a silence; *pending where it still may.
  bool crc_zero_follows(std::size_t pos, bool at_end, bool* pending) const;
  // Whether more bytes may still extend the CRC search from `pos` (no silence ended it, the
  // input goes on, and it is shorter than the longest frame): its "no zero" is not final.
  [[nodiscard]] bool crc_search_may_go_on(const CrcScan& scan, std::size_t pos, bool at_end) const {
    return !scan.ended_at_silence && !at_end && buffered() - pos < kMaxAdu;
  }
  void classify_span(std::size_t length);
  [[nodiscard]] std::size_t first_whole_frame_before(std::size_t end) const;
  bool boundary_at(std::size_t pos) const;
  [[nodiscard]] bool read_bounded(std::size_t pos, std::size_t length) const;
  [[nodiscard]] bool silence_before(Nanos gap) const { return gap >= t3_5_ + resolution_; }
  // A pause longer than t1.5 beyond what the resolution may hide: the kT15 flag, and where a
  // span that holds no frame is cut (first_t15_silence()). An unknown gap is none.
  [[nodiscard]] bool breaks_t15(Nanos gap) const {
    return gap != kUnknownTime && gap - resolution_ > t1_5_;
  }
  CrcScan& extended_scan(std::size_t pos) const;
  void run_crc_on(std::size_t pos, CrcScan& scan, std::size_t limit) const;
  [[gnu::noinline]] void extend_scan_otherwise(std::size_t pos, CrcScan& scan,
                                               std::size_t limit) const;
  std::size_t first_silence(std::size_t from, std::size_t to) const;
  bool contiguous_at(std::size_t pos) const;
  [[nodiscard]] bool paused_before(std::size_t pos) const;
  [[nodiscard]] std::size_t first_t15_silence(std::size_t length) const;
  [[nodiscard]] bool starts_a_cut_frame(std::size_t pos, std::size_t end) const;
  bool is_turnaround_glitch(const Record& noise) const;
  bool plausible_start(std::size_t pos) const;
  bool awaited_response_at(std::size_t pos) const;
  std::size_t predicted_length(std::size_t pos) const;

  // `crc_confirmed`: the CRC was just found zero over [0, length).
  void emit_frame(std::size_t length, bool crc_confirmed = false);
  void emit_noise(std::size_t length);
  void flush_noise();
  void consume(std::size_t length);
  // Fills `rec` with bytes [from, from + length) and their times and line errors; returns
  // the longest silence between them (kUnknownTime when none is measured).
  Nanos fill_record(Record& rec, std::size_t from, std::size_t length) const;

  [[nodiscard]] std::size_t buffered() const { return end_ - begin_; }
  [[nodiscard]] std::uint8_t byte_at(std::size_t pos) const { return bytes_[begin_ + pos]; }
  [[nodiscard]] const ByteInfo& info_at(std::size_t pos) const { return info_[begin_ + pos]; }

  FramerConfig config_;
  RecordSink& out_;
  Nanos char_time_;
  Nanos t1_5_;
  Nanos t3_5_;
  Nanos resolution_;
  std::uint64_t chunks_ = 0;
  std::uint64_t batched_chunks_ = 0;  // reads that returned more than one byte
  bool watching_reads_ = false;       // starts are watched across reads like the last one

  std::array<std::uint8_t, kWindow> bytes_{};
  std::array<ByteInfo, kWindow> info_{};
  std::size_t begin_ = 0;
  std::size_t end_ = 0;
  std::uint64_t consumed_ = 0;  // bytes emitted so far: the absolute position of begin_
  // Positions from here on (absolute) may show a silence; those before it, down to the
  // window's second byte, were looked at with the current resolution and do not.
  std::uint64_t silence_search_from_ = 0;
  mutable CrcScanCache crc_scans_;
  mutable CrcZeroIndex crc_zeros_;  // answers the scans
  // first_silence()'s last answer, in absolute positions: no silence in [from, found), and
  // a silence at found unless found == to. Judged with `resolution`.
  struct SilenceLook {
    std::uint64_t from = 0;
    std::uint64_t found = 0;
    std::uint64_t to = 0;
    Nanos resolution = -1;
  };
  mutable SilenceLook last_silence_look_;
  // Window positions (absolute modulo kWindow) known not to start a confirmable frame
  // whatever bytes come next: searches skip them. Cleared when the resolution changes.
  WindowBits<kWindow> settled_;
  // Set during a search when a frame it depends on may still be completed by more bytes.
  mutable bool answer_may_change_ = false;
  QuietStarts quiet_starts_;
  std::uint64_t epoch_ = 1;  // what the bus awaits and the resolution (see quiet_starts.hpp)

  Nanos last_byte_end_ = kUnknownTime;  // end of the newest byte pushed
  Nanos last_record_end_ = kUnknownTime;
  bool last_record_was_frame_ = false;
  // When the last record is a turnaround glitch: time from the frame before it to its end.
  Nanos glitch_since_frame_ = kUnknownTime;
  // Positions [1, scan_resume_) of the window are known not to start a confirmable frame.
  std::size_t scan_resume_ = 1;
  std::bitset<256> active_slaves_;  // slaves seen in CRC-valid frames
  std::uint64_t next_seq_ = 0;

  Record noise_;  // noise bytes accumulate here until a frame follows or it is full
  Record scratch_;
  Record noise_out_;  // a noise record while the sink handles it

  // The last read came late (Chunk::read_late): the silence after it is not measured.
  bool after_late_read_ = false;
  // The largest read so far, and whether the last one was as large (and of at least
  // kFullReadAtLeast bytes): see quiet_to_decide().
  std::size_t largest_read_ = 0;
  bool last_read_filled_ = false;
  bool expect_response_ = false;
  std::uint8_t expected_slave_ = 0;
  std::uint8_t expected_function_ = 0;
};

// Most bytes of a per-byte read bring a frame no nearer to a decision: its head waits for a
// predicted length (a request's fixed size, a response's byte count) that is not there yet,
// or a CRC zero (a function code with no length rule). push() would then find advance()
// with nothing to do, store the byte, and decide(false) would run the watches on (none:
// only the mark moves), find the head's remembered answer, "waits" (quiet_starts.hpp), run
// the head's CRC search on by the byte (no zero), look at the new byte for a silence (none:
// only that mark moves), and wait. Here that is done directly, under exactly those
// conditions, all checked before anything changes; anything else (a silence to decide, a
// watch, a search to make, a silence before the byte, a full window, a CRC zero, a CRC
// search that does not cover the window) is left to push().
inline bool Framer::push_if_head_waits(std::uint8_t byte, Nanos now, std::uint64_t origin) {
  if (last_read_filled_) return false;  // push() notes that this read fills nothing
  if (buffered() == 0) return push_first_byte_if_it_waits(byte, now, origin);
  Nanos latest = 0;
  return push_reads_to_waiting_head(&byte, &now, origin, 1, latest) == 1;
}

inline std::size_t Framer::push_reads_while_head_waits(const ByteReads& reads, std::size_t first,
                                                       Nanos& latest) {
  if (after_late_read_) return 0;  // the first read's silence is not measured
  std::size_t i = first;
  if (i < reads.size() && buffered() == 0) {
    if (!push_first_byte_if_it_waits(reads.bytes[i], reads.t_ends[i], reads.origin + i)) return 0;
    latest = reads.t_ends[i];
    ++i;
  }
  if (i < reads.size()) {
    Nanos run_latest = 0;
    const std::size_t taken = push_reads_to_waiting_head(
        reads.bytes.data() + i, reads.t_ends + i, reads.origin + i, reads.size() - i, run_latest);
    if (taken > 0) {
      latest = i > first ? std::max(latest, run_latest) : run_latest;
      i += taken;
    }
  }
  return i - first;
}

// A frame's first byte, into an empty window: advance() has nothing to decide (unless noise
// is held), and decide(false) would run the watches on, search at the head (one byte, too
// short for any frame: it waits, and the search remembers that) and find no position after
// it to look at for a silence.
inline bool Framer::push_first_byte_if_it_waits(std::uint8_t byte, Nanos now,
                                                std::uint64_t origin) {
  if (end_ == kWindow || quiet_starts_.any_watched() || last_byte_end_ == kUnknownTime) {
    return false;
  }
  if (noise_.size != 0) return false;  // advance() may end the noise
  const auto [end, gap] = time_after(now, last_byte_end_, char_time_);
  const std::uint64_t window_end = consumed_ + 1;
  settled_.clear(consumed_ % kWindow);  // a new position, not looked at yet
  bytes_[end_] = byte;
  info_[end_] = ByteInfo{end, gap, origin, 1, 0, true};
  ++end_;
  ++chunks_;
  watching_reads_ = true;
  last_byte_end_ = end;
  quiet_starts_.unwatch_all(window_end);  // run_quiet_watch_on() with nothing watched
  bool pending = false;
  settled_or_confirmed_length(0, false, &pending);  // fewer bytes than a frame: 0, pending
  silence_search_from_ = std::max(silence_search_from_, window_end);
  return true;
}

// Reads bytes[k], completed at t_ends[k], one after the other, to a head (of a window that
// holds bytes) that waits. Of the conditions above, all but a read's own timing hold for the
// whole run once they hold for its first read, within the bounds set below: nothing these
// reads store changes the head's remembered answer, the watches or the epoch, and each
// read leaves the silence mark where the next one needs it. So only the timing is asked
// read by read. Returns how many were taken, and the latest completion time among them.
inline std::size_t Framer::push_reads_to_waiting_head(const std::uint8_t* bytes,
                                                      const Nanos* t_ends, std::uint64_t origin,
                                                      std::size_t count, Nanos& latest) {
  const std::size_t held = buffered();
  if (held == 0 || end_ == kWindow || held + 1 >= kMaxPending || quiet_starts_.any_watched() ||
      last_byte_end_ == kUnknownTime || last_read_filled_) {
    return 0;
  }
  const std::uint64_t first_end = consumed_ + held + 1;  // the window's end with the first read
  if (silence_search_from_ != first_end - 1 || settled_.test(consumed_ % kWindow)) return 0;
  const QuietStart* head = quiet_starts_.find(consumed_, epoch_, first_end);
  if (head == nullptr || !head->pending) return 0;
  // The remembered answer holds while the window ends before head->until; the window's room
  // and the forced decision (kMaxPending) bound the run as they bound each read.
  // A head that waits on its CRC search (a function code with no length rule) waits on as
  // long as the search, run on over the new bytes, finds no zero (nor a silence, as below).
  const bool waits_on_crc = head->watch_crc_scan;
  std::size_t limit = static_cast<std::size_t>(std::min<std::uint64_t>(
      {count, head->until - first_end, kWindow - end_, kMaxPending - (held + 1)}));
  if (waits_on_crc) [[unlikely]] {
    limit = quiet_crc_steps(bytes, limit);
  }
  const Nanos quiet = quiet_to_decide();
  const Nanos char_time = char_time_;
  // In locals: the byte stores may alias any member.
  std::uint8_t* const to_bytes = bytes_.data() + end_;
  ByteInfo* const to_info = info_.data() + end_;
  Nanos last = last_byte_end_;
  Nanos newest = t_ends[0];
  std::size_t k = 0;
  for (; k < limit; ++k) {
    const Nanos now = t_ends[k];
    if (now - last >= quiet) break;  // advance() would decide
    const auto [end, gap] = time_after(now, last, char_time);
    if (silence_before(gap)) break;
    settled_.clear((first_end - 1 + k) % kWindow);  // a new position, not looked at yet
    to_bytes[k] = bytes[k];
    to_info[k] = ByteInfo{end, gap, origin + k, 1, 0, true};
    newest = std::max(newest, now);
    last = end;
  }
  if (k == 0) return 0;
  if (waits_on_crc) [[unlikely]] {
    run_crc_steps(to_bytes, k);  // as extended_scan() would have
  }
  const std::uint64_t window_end = first_end - 1 + k;
  end_ += k;
  chunks_ += k;
  watching_reads_ = true;
  last_byte_end_ = last;
  quiet_starts_.unwatch_all(window_end);  // run_quiet_watch_on() with nothing watched
  silence_search_from_ = window_end;      // the new bytes show no silence
  latest = newest;
  return k;
}

}  // namespace rtu

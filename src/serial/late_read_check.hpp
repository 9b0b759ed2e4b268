#pragma once
// Whether a live read came late. A read's time is when it completed, taken as when its last
// byte arrived: true while the reading thread sleeps in the read's wait, since arriving
// bytes wake it at once. But a thread that is busy (handling the read before, or another
// port's) or runnable and waiting for a CPU (a loaded host) leaves arriving bytes waiting,
// and the read then completes later than they arrived, with no sign in the bytes. Linux
// tells a thread its CPU time and how long it waited for a CPU
// (/proc/thread-self/schedstat); their sum bounds how late a read came (below). Beyond the
// timing resolution (which assumes that much of any read), the read's time is no evidence
// of the silences next to it (Chunk::read_late).
#include <cstdint>
#include <optional>
#include <string_view>
#include <thread>

#include "core/time.hpp"

namespace rtu {

// How long the calling thread has waited for a CPU (runnable, not running), in ns since it
// started; nullopt where the kernel does not tell (no schedstats). The file is opened, and
// opened again, for the thread that asks.
class ThreadRunDelay {
 public:
  ThreadRunDelay() = default;
  ThreadRunDelay(const ThreadRunDelay&) = delete;
  ThreadRunDelay& operator=(const ThreadRunDelay&) = delete;
  ~ThreadRunDelay();

  [[nodiscard]] std::optional<Nanos> now();

 private:
  int fd_ = -1;
  std::thread::id opened_for_;
  bool unavailable_ = false;
};

// "<on-cpu ns> <run-queue wait ns> <timeslices>" (/proc/thread-self/schedstat): the wait;
// nullopt when the text is not that.
std::optional<Nanos> parse_schedstat_run_delay(std::string_view text);

// The calling thread's CPU time (CLOCK_THREAD_CPUTIME_ID, current to the nanosecond, where
// schedstat's own field lags a running thread by up to a scheduler tick).
Nanos thread_cpu_time();

// The bound is the thread's busy time (CPU time plus waiting for a CPU) since the last
// moment it was known to wait for bytes that had not come yet: when the read was issued
// with no input pending (the bytes came later, and from then on the thread slept, which
// they ended at once, or was busy), or any later such moment the owner notes (a timer's
// handler finding no input pending). Input pending at such a moment may have waited since
// an earlier one: the bound then runs from that earlier one, which holds for every read
// after it too. A read that completes within the allowance of that moment is on time
// without asking the kernel more. After a quick handling the wait for a CPU is not read
// anew, so the bound also counts such waits since it last was: never less than the truth.
class LateReadCheck {
 public:
  // `allowed`: the lateness the timing resolution already allows for.
  explicit LateReadCheck(Nanos allowed) : allowed_(allowed) {}

  // A moment the thread waits for bytes: `input_pending` when some had come already.
  void waiting(bool input_pending);
  // Whether the read that completed last was handled so quickly that bytes arriving
  // meanwhile waited for no time that matters (kQuickHandling): the next read can then be
  // taken as issued with no input pending (waiting_after_quick_handling()), without asking
  // the driver, nor the kernel for the wait for a CPU, which so short a handling hardly
  // added to.
  [[nodiscard]] bool handled_quickly() const;
  void waiting_after_quick_handling();
  static constexpr Nanos kQuickHandling = 50 * kNanosPerMicro;
  // Asked at each read's completion, on the reading thread: whether it came later than
  // allowed. A read with no such moment before it (the first) is not judged.
  bool read_came_late();
  // A new start (the port opened again, its resolution perhaps another).
  void restart(Nanos allowed);

  [[nodiscard]] std::uint64_t late_reads() const { return late_reads_; }

 private:
  void take_moment();  // now is the moment a read's lateness is bounded from

  ThreadRunDelay run_delay_;
  std::optional<Nanos> waited_at_;       // monotonic time of the moment
  std::optional<Nanos> completed_at_;    // monotonic time of the last read's completion
  Nanos cpu_at_waiting_ = 0;             // the thread's CPU time then
  std::optional<Nanos> run_delay_seen_;  // at the last completion that asked
  // The thread's CPU time at the last completion, where that completion read it.
  std::optional<Nanos> cpu_at_completion_;
  Nanos allowed_;
  std::uint64_t late_reads_ = 0;
};

}  // namespace rtu

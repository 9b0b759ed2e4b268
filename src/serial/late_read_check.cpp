#include "serial/late_read_check.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <charconv>
#include <ctime>

namespace rtu {
namespace {

Nanos read_clock(clockid_t id) {
  timespec t{};
  ::clock_gettime(id, &t);
  return static_cast<Nanos>(t.tv_sec) * kNanosPerSecond + t.tv_nsec;
}

}  // namespace

ThreadRunDelay::~ThreadRunDelay() {
  if (fd_ >= 0) ::close(fd_);
}

std::optional<Nanos> ThreadRunDelay::now() {
  if (unavailable_) return std::nullopt;
  if (fd_ < 0 || opened_for_ != std::this_thread::get_id()) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = ::open("/proc/thread-self/schedstat", O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) {
      unavailable_ = true;
      return std::nullopt;
    }
    opened_for_ = std::this_thread::get_id();
  }
  char text[96];
  const ssize_t n = ::pread(fd_, text, sizeof text, 0);
  if (n <= 0) return std::nullopt;
  return parse_schedstat_run_delay({text, static_cast<std::size_t>(n)});
}

std::optional<Nanos> parse_schedstat_run_delay(std::string_view text) {
  Nanos fields[2] = {0, 0};
  const char* at = text.data();
  const char* const end = text.data() + text.size();
  for (Nanos& field : fields) {
    while (at < end && *at == ' ') ++at;
    const auto [next, error] = std::from_chars(at, end, field);
    if (error != std::errc{} || field < 0 || next == at) return std::nullopt;
    at = next;
  }
  if (at == end || (*at != ' ' && *at != '\n')) return std::nullopt;
  return fields[1];
}

Nanos thread_cpu_time() {
  return read_clock(CLOCK_THREAD_CPUTIME_ID);
}

void LateReadCheck::waiting(bool input_pending) {
  if (input_pending) return;
  // A long handling may have waited for a CPU itself: that is no delay of the next read.
  run_delay_seen_ = run_delay_.now();
  take_moment();
}

void LateReadCheck::waiting_after_quick_handling() {
  if (!run_delay_seen_) run_delay_seen_ = run_delay_.now();  // the first time only
  if (!cpu_at_completion_) {
    take_moment();
    return;
  }
  // The CPU time the completion just before read saves reading it again (a system call,
  // not served by the vDSO, at nearly every read of a busy line): the quick handling since
  // then counts as busy too, so the bound grows by at most kQuickHandling, never shrinks.
  waited_at_ = read_clock(CLOCK_MONOTONIC);
  cpu_at_waiting_ = *cpu_at_completion_;
}

void LateReadCheck::take_moment() {
  waited_at_ = read_clock(CLOCK_MONOTONIC);
  cpu_at_waiting_ = thread_cpu_time();
}

bool LateReadCheck::handled_quickly() const {
  return completed_at_ && read_clock(CLOCK_MONOTONIC) - *completed_at_ <= kQuickHandling;
}

bool LateReadCheck::read_came_late() {
  const Nanos now = read_clock(CLOCK_MONOTONIC);
  completed_at_ = now;
  cpu_at_completion_.reset();
  // The moment stays until a later one is known: no input was pending then, neither for
  // this read nor for any after it.
  if (!waited_at_ || now - *waited_at_ <= allowed_) return false;
  const std::optional<Nanos> run_delay = run_delay_.now();
  if (!run_delay || !run_delay_seen_) {
    run_delay_seen_ = run_delay;
    return false;  // the kernel does not tell: the read is taken as it comes, as before
  }
  cpu_at_completion_ = thread_cpu_time();
  const Nanos busy = (*cpu_at_completion_ - cpu_at_waiting_) + (*run_delay - *run_delay_seen_);
  run_delay_seen_ = run_delay;
  const bool late = busy > allowed_;
  if (late) ++late_reads_;
  return late;
}

void LateReadCheck::restart(Nanos allowed) {
  allowed_ = allowed;
  waited_at_.reset();
  completed_at_.reset();
  cpu_at_completion_.reset();
}

}  // namespace rtu

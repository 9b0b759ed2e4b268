#include "core/thread_priority.hpp"

#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>

namespace rtu {

std::size_t usable_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  const int count = CPU_COUNT(&set);
  return count > 0 ? static_cast<std::size_t>(count) : 1;
}

bool yield_priority_if_crowded(std::size_t threads, int nice_steps) {
  if (nice_steps <= 0 || usable_cores() >= threads) return false;
  // PRIO_PROCESS with a thread's id sets that thread's nice value alone on Linux.
  const auto self = static_cast<id_t>(gettid());
  errno = 0;
  const int now = getpriority(PRIO_PROCESS, self);  // -1 is a valid nice value: errno tells
  if (errno != 0) return false;
  return setpriority(PRIO_PROCESS, self, now + nice_steps) == 0;
}

}  // namespace rtu

#pragma once
// Test support for the scheduling hints (core/thread_priority.hpp): a thread's own nice value,
// and a body run on a new thread pinned to some of the usable cores.
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstddef>
#include <thread>

namespace rtu::testing {

inline int nice_of_this_thread() {
  return getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));
}

// Runs `body` on a thread of its own, pinned to the first `cores` of the usable cores (0: all);
// threads it starts inherit that affinity.
template <typename Body>
void on_new_thread(std::size_t cores, Body body) {
  std::thread t([&] {
    if (cores > 0) {
      cpu_set_t all;
      CPU_ZERO(&all);
      ASSERT_EQ(sched_getaffinity(0, sizeof all, &all), 0);
      cpu_set_t pinned;
      CPU_ZERO(&pinned);
      std::size_t kept = 0;
      for (std::size_t cpu = 0; cpu < std::size_t{CPU_SETSIZE} && kept < cores; ++cpu) {
        if (CPU_ISSET(cpu, &all)) {
          CPU_SET(cpu, &pinned);
          ++kept;
        }
      }
      ASSERT_EQ(sched_setaffinity(0, sizeof pinned, &pinned), 0);
    }
    body();
  });
  t.join();
}

}  // namespace rtu::testing

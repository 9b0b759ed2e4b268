// The reading thread's yielding to the framing: a thread lowers its own priority only where
// the threads outnumber its cores, and only its own.
#include "core/thread_priority.hpp"

#include <gtest/gtest.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <thread>

namespace rtu {
namespace {

int nice_of_this_thread() {
  return getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));
}

// Runs `body` on a thread of its own, pinned to `cores` of the usable cores (0: all).
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

TEST(ThreadPriority, UsableCoresFollowTheAffinity) {
  EXPECT_GE(usable_cores(), 1U);
  on_new_thread(1, [] { EXPECT_EQ(usable_cores(), 1U); });
}

TEST(ThreadPriority, AThreadYieldsWhereTheThreadsOutnumberItsCores) {
  const int before = nice_of_this_thread();
  on_new_thread(1, [before] {
    EXPECT_EQ(nice_of_this_thread(), before);  // a new thread starts at its creator's level
    if (before + 3 > 19) GTEST_SKIP() << "already at the lowest priority";
    EXPECT_TRUE(yield_priority_if_crowded(3, 3));
    EXPECT_EQ(nice_of_this_thread(), before + 3);
  });
  EXPECT_EQ(nice_of_this_thread(), before);  // the thread that yielded, alone
}

TEST(ThreadPriority, AThreadKeepsItsPriorityWhereEachThreadHasACore) {
  const int before = nice_of_this_thread();
  const std::size_t cores = usable_cores();
  on_new_thread(0, [before, cores] {
    EXPECT_FALSE(yield_priority_if_crowded(cores, 3));
    EXPECT_FALSE(yield_priority_if_crowded(1, 3));
    EXPECT_FALSE(yield_priority_if_crowded(cores + 1, 0));  // no steps, nothing to do
    EXPECT_EQ(nice_of_this_thread(), before);
  });
}

}  // namespace
}  // namespace rtu

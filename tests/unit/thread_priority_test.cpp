// The reading thread's yielding to the framing: a thread lowers its own priority only where
// the threads outnumber its cores, and only its own.
#include "core/thread_priority.hpp"

#include <gtest/gtest.h>

#include "pinned_thread.hpp"

namespace rtu {
namespace {

using testing::nice_of_this_thread;
using testing::on_new_thread;

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

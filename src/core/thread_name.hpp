#pragma once
// Names for the threads a run spreads its stages over, as `top -H`, `ps -L`, perf and
// /proc/PID/task/TID/comm show them: where a replay's time went (tools/bench/thread_time.py),
// or which stage of a plant's long run is busy, is then read per stage, not per thread id.
#include <string>
#include <string_view>

namespace rtu {

// Names the calling thread. Linux keeps 15 characters; a thread that cannot be named runs on
// as it was: a name is a label, never needed for the work.
void name_this_thread(std::string_view name);

// The calling thread's name (the program's, until it is named).
std::string this_thread_name();

}  // namespace rtu

#pragma once
// Scheduling hints for the threads a decoding pass spreads its stages over.
#include <cstddef>

namespace rtu {

// How many cores the calling thread may run on (its CPU affinity), at least 1.
std::size_t usable_cores();

// Lowers the calling thread's priority by `nice_steps` nice levels when `threads` threads
// share the work and fewer cores than that are usable; returns whether it did. The scheduler
// shares the cores evenly among the threads that can run, which starves the busiest
// stage of a pipeline whenever a lighter one could run ahead; a lighter stage that yields
// leaves the busiest its core. Only the calling thread changes (Linux keeps a nice value per
// thread), and a thread that cannot change it runs on as it was: this is a hint.
bool yield_priority_if_crowded(std::size_t threads, int nice_steps);

}  // namespace rtu

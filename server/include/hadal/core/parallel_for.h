// A parallel loop as a value: whoever runs a piece of work split into independent tasks (a camera
// frame's bands, say) takes one of these and stays free of any thread pool. Callers pass the ray-cast
// workers' loop, a benchmark's threads, or serial_for.
#pragma once

#include <cstddef>
#include <functional>

namespace hadal {

// Runs task(i) for every i in [0, count), in any order and on any threads, and returns when all are
// done. Tasks must not depend on the order they run in.
using ParallelFor = std::function<void(std::size_t count, const std::function<void(std::size_t)>& task)>;

inline void serial_for(std::size_t count, const std::function<void(std::size_t)>& task) {
  for (std::size_t i = 0; i < count; ++i) task(i);
}

}  // namespace hadal

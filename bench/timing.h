// Wall-clock helpers shared by the benchmarks: a steady clock, seconds since a start, and the median of
// repeated measurements (the mean of the two middle values for an even count).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <vector>

namespace hadal::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace hadal::bench

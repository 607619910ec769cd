// Sim time [s] <-> builtin_interfaces/Time (sec, nanosec with nanosec in [0, 1e9)).
#pragma once

#include <builtin_interfaces.h>

#include <cmath>
#include <cstdint>

namespace hadal::dds {

// Rounded to the nearest nanosecond.
inline builtin_interfaces::msg::Time to_time_msg(double time_s) {
  const auto total_ns = static_cast<std::int64_t>(std::llround(time_s * 1e9));
  std::int64_t sec = total_ns / 1000000000;
  std::int64_t nanosec = total_ns % 1000000000;
  if (nanosec < 0) {
    nanosec += 1000000000;
    sec -= 1;
  }
  builtin_interfaces::msg::Time msg;
  msg.sec(static_cast<std::int32_t>(sec));
  msg.nanosec(static_cast<std::uint32_t>(nanosec));
  return msg;
}

inline double from_time_msg(const builtin_interfaces::msg::Time& time) {
  return static_cast<double>(time.sec()) + 1e-9 * static_cast<double>(time.nanosec());
}

}  // namespace hadal::dds

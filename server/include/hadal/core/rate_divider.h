// RateDivider: decides at which physics steps a stream of rate_hz samples is due, for any rate, without
// drift. Sample n is due at t_n = n / rate_hz; it fires at the first step whose time t = k * dt reaches
// t_n (to within a relative 1e-9, so exact multiples are not missed to rounding). Because t_n is computed
// from n, never accumulated, a 30 Hz stream in a 500 Hz loop delivers exactly 30 samples per simulated
// second over any run length. Rates above the physics rate fire every step.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace hadal {

class RateDivider {
 public:
  RateDivider() = default;
  explicit RateDivider(double rate_hz) : rate_hz_(rate_hz) {}

  // True when a sample is due at sim time `time_s` (call once per step, with non-decreasing times).
  bool due(double time_s) {
    if (!(rate_hz_ > 0.0)) return false;
    const double t_next = static_cast<double>(next_) / rate_hz_;
    if (time_s + 1e-9 * std::max(1.0, std::abs(t_next)) < t_next) return false;
    // Skip samples that fall between two steps (rate above the physics rate): one per step at most.
    next_ = static_cast<std::uint64_t>(std::floor(time_s * rate_hz_ * (1.0 + 1e-12) + 1e-9)) + 1;
    return true;
  }

  double rate_hz() const { return rate_hz_; }
  void reset() { next_ = 0; }

 private:
  double rate_hz_ = 0.0;
  std::uint64_t next_ = 0;
};

// The same schedule without state, for streams sampled inside the simulation (their schedule must
// survive a SimState restore): true when a sample of a rate_hz stream is due at physics step
// `step` >= 1 (time step * dt), i.e. when some t_n = n / rate_hz lies in (t_{step-1}, t_step].
inline bool sample_due(std::uint64_t step, double dt, double rate_hz) {
  if (!(rate_hz > 0.0) || step == 0) return false;
  const auto samples_until = [&](std::uint64_t k) {  // samples with t_n <= k dt (n = 0, 1, ...)
    return static_cast<std::uint64_t>(std::floor(static_cast<double>(k) * dt * rate_hz * (1.0 + 1e-12) + 1e-9));
  };
  return samples_until(step) > samples_until(step - 1);
}

}  // namespace hadal

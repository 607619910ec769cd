#include "hadal/core/rate_divider.h"

#include <gtest/gtest.h>

namespace hadal {
namespace {

// Counts due samples over `seconds` of a loop at physics_hz; times are k * dt as in Simulation.
int count_samples(double rate_hz, double physics_hz, double seconds) {
  RateDivider divider(rate_hz);
  const double dt = 1.0 / physics_hz;
  const auto steps = static_cast<std::uint64_t>(std::llround(seconds * physics_hz));
  int count = 0;
  for (std::uint64_t k = 0; k <= steps; ++k) count += divider.due(static_cast<double>(k) * dt) ? 1 : 0;
  return count;
}

TEST(RateDividerTest, DividingRatesFireExactly) {
  // t = 0 fires, then one sample per period: rate * T + 1 samples in [0, T].
  EXPECT_EQ(count_samples(50.0, 500.0, 100.0), 5001);
  EXPECT_EQ(count_samples(100.0, 500.0, 100.0), 10001);
  EXPECT_EQ(count_samples(500.0, 500.0, 10.0), 5001);
}

TEST(RateDividerTest, NonDividingRatesDoNotDrift) {
  // 30 Hz in a 500 Hz loop: periods of 16 or 17 steps, still exactly 30 per second over an hour.
  EXPECT_EQ(count_samples(30.0, 500.0, 3600.0), 30 * 3600 + 1);
  EXPECT_EQ(count_samples(7.0, 1000.0, 3600.0), 7 * 3600 + 1);
}

TEST(RateDividerTest, FasterThanPhysicsFiresEveryStep) {
  EXPECT_EQ(count_samples(2000.0, 500.0, 1.0), 501);
}

TEST(RateDividerTest, SamplesFallOnOrJustAfterTheirDueTime) {
  RateDivider divider(30.0);
  const double dt = 1.0 / 500.0;
  int n = 0;
  for (int k = 0; k <= 5000; ++k) {
    const double t = k * dt;
    if (divider.due(t)) {
      const double t_due = n / 30.0;
      EXPECT_GE(t, t_due - 1e-9);
      EXPECT_LT(t, t_due + dt);  // never more than one step late
      ++n;
    }
  }
  EXPECT_EQ(n, 301);
}

TEST(RateDividerTest, ZeroRateNeverFires) { EXPECT_EQ(count_samples(0.0, 500.0, 1.0), 0); }

// The stateless schedule of in-simulation sensors: a 200 Hz sensor in a 1 kHz loop samples every 5th
// step; 30 Hz in 500 Hz gives exactly 30 samples per second over an hour (steps 1.. k, t = k dt), and
// agrees step for step with RateDivider after its t = 0 sample.
TEST(RateDividerTest, StatelessScheduleMatchesTheDivider) {
  for (std::uint64_t k = 1; k <= 20; ++k) EXPECT_EQ(sample_due(k, 1e-3, 200.0), k % 5 == 0) << k;
  std::uint64_t count = 0;
  for (std::uint64_t k = 1; k <= 3600u * 500u; ++k) count += sample_due(k, 1.0 / 500.0, 30.0) ? 1 : 0;
  EXPECT_EQ(count, 3600u * 30u);
  for (double rate : {7.0, 30.0, 333.0, 500.0, 2000.0}) {
    RateDivider divider(rate);
    const double dt = 1.0 / 500.0;
    divider.due(0.0);
    for (std::uint64_t k = 1; k <= 5000; ++k) {
      ASSERT_EQ(sample_due(k, dt, rate), divider.due(static_cast<double>(k) * dt)) << rate << " " << k;
    }
  }
  EXPECT_FALSE(sample_due(0, 1e-3, 100.0));
  EXPECT_FALSE(sample_due(5, 1e-3, 0.0));
}

}  // namespace
}  // namespace hadal

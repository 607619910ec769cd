#include "hadal/physics/seawater.h"

#include <gtest/gtest.h>

namespace hadal::physics {
namespace {

// UNESCO 1983 (Tech. Pap. Mar. Sci. 44) check values, printed there to 5 decimals: tolerance 1e-5 kg/m^3.
TEST(SeawaterTest, Eos80CheckValues) {
  EXPECT_NEAR(density_eos80(35.0, 5.0, 10000.0), 1069.48914, 1e-5);
  EXPECT_NEAR(density_eos80(35.0, 25.0, 0.0), 1023.34306, 1e-5);
  EXPECT_NEAR(density_eos80(0.0, 5.0, 0.0), 999.96675, 1e-5);
  EXPECT_NEAR(density_eos80(35.0, 5.0, 0.0), 1027.67547, 1e-5);
  EXPECT_NEAR(density_eos80(0.0, 25.0, 10000.0), 1037.90204, 1e-5);
}

// Secant bulk modulus check value (UNESCO 1983): K(35, 25, 1000 bar) = 27108.94504 bar, to 1e-5 bar.
TEST(SeawaterTest, SecantBulkModulusCheckValue) {
  EXPECT_NEAR(secant_bulk_modulus_eos80_bar(35.0, 25.0, 10000.0), 27108.94504, 1e-5);
}

// Chen & Millero check value in UNESCO 1983: c(40, 40 degC, 10000 dbar) = 1731.995 m/s (printed to 1e-3).
// c(35, 20, 0): UNESCO 1983's sound-speed table gives 1521.5 m/s (rounded to 0.1; the formula gives 1521.46).
TEST(SeawaterTest, SoundSpeedCheckValues) {
  EXPECT_NEAR(sound_speed_unesco(40.0, 40.0, 10000.0), 1731.995, 1e-3);
  EXPECT_NEAR(sound_speed_unesco(35.0, 20.0, 0.0), 1521.5, 0.05);
}

TEST(SeawaterTest, Its90ToIpts68) { EXPECT_DOUBLE_EQ(its90_to_ipts68(10.0), 10.0024); }

}  // namespace
}  // namespace hadal::physics

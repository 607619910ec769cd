#include "hadal/physics/seawater.h"

#include <gtest/gtest.h>

#include <cmath>

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

// Ainslie & McColm (1998, J. Acoust. Soc. Am. 103(3), 1671-1672), a simplified fit to Francois & Garrison
// published with its accuracy: within 10 % of it from 100 Hz to 1 MHz for -6 < T < 35 degC, 7.7 < pH < 8.3,
// 5 < S < 50 and 0 < D < 7 km. f in kHz, D in m; [dB/km].
double ainslie_mccolm_db_per_km(double f, double t, double s, double d, double ph) {
  const double f1 = 0.78 * std::sqrt(s / 35.0) * std::exp(t / 26.0), f2 = 42.0 * std::exp(t / 17.0);
  const double boric = 0.106 * std::exp((ph - 8.0) / 0.56) * f1 * f * f / (f1 * f1 + f * f);
  const double mgso4 = 0.52 * (s / 35.0) * (1.0 + t / 43.0) * std::exp(-d / 6000.0) * f2 * f * f / (f2 * f2 + f * f);
  const double water = 0.00049 * std::exp(-(t / 27.0 + d / 17000.0)) * f * f;
  return boric + mgso4 + water;
}

// Francois & Garrison against Ainslie & McColm's stated 10 % over a grid inside its range of validity
// (sonar frequencies 10 kHz to 1 MHz, cold deep water to warm surface water; water above 10 degC only down to
// 1000 m, as in the ocean).
TEST(SeawaterTest, AbsorptionWithinTenPercentOfAinslieMcColm) {
  for (double f_khz : {10.0, 30.0, 100.0, 300.0, 750.0, 1000.0}) {
    for (double t : {2.0, 4.0, 10.0, 20.0, 28.0}) {
      for (double d : {0.0, 1000.0, 4000.0, 6000.0}) {
        if (t > 10.0 && d > 1000.0) continue;
        for (double ph : {7.8, 8.0, 8.2}) {
          const double fg = absorption_francois_garrison_db_per_km(f_khz * 1000.0, t, 35.0, d, ph);
          const double am = ainslie_mccolm_db_per_km(f_khz, t, 35.0, d, ph);
          EXPECT_NEAR(fg / am, 1.0, 0.10) << f_khz << " kHz, " << t << " degC, " << d << " m, pH " << ph;
        }
      }
    }
  }
}

// The three terms by hand at 100 kHz, 10 degC, S = 35, surface, pH 8 (c = 1485.75 m/s): boric acid
// 0.1157, MgSO4 30.41, pure water 3.108 dB/km; 33.63 dB/km in all (the textbook ~30-40 dB/km at 100 kHz).
// Tolerance 0.01 dB/km: the hand values' rounding.
TEST(SeawaterTest, AbsorptionAt100kHz) {
  EXPECT_NEAR(absorption_francois_garrison_db_per_km(100e3, 10.0, 35.0, 0.0, 8.0), 33.63, 0.01);
  // Absorption grows with frequency and falls with depth (pressure) at sonar frequencies.
  EXPECT_GT(absorption_francois_garrison_db_per_km(400e3, 4.0, 35.0, 0.0), absorption_francois_garrison_db_per_km(200e3, 4.0, 35.0, 0.0));
  EXPECT_LT(absorption_francois_garrison_db_per_km(400e3, 4.0, 35.0, 3000.0), absorption_francois_garrison_db_per_km(400e3, 4.0, 35.0, 0.0));
}

// Saunders (1990): T68 = 1.00024 T90, a scale factor, not an offset, over the oceanographic range: 0 stays
// 0, a negative temperature moves down, 30 degC up by 0.0072 K. Values from the relation by hand; exact to
// the last bits of a double (4 ulp).
TEST(SeawaterTest, Its90ToIpts68) {
  EXPECT_EQ(its90_to_ipts68(0.0), 0.0);
  EXPECT_DOUBLE_EQ(its90_to_ipts68(-2.0), -2.00048);
  EXPECT_DOUBLE_EQ(its90_to_ipts68(10.0), 10.0024);
  EXPECT_DOUBLE_EQ(its90_to_ipts68(30.0), 30.0072);
}

}  // namespace
}  // namespace hadal::physics

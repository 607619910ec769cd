#include "hadal/physics/seawater.h"

#include <cmath>

namespace hadal::physics {

namespace {

// rho(S, T, 0) [kg/m^3]: standard mean ocean water plus the salinity terms of EOS-80.
double density_at_surface(double s, double t) {
  const double rho_w = 999.842594 +
                       t * (6.793952e-2 + t * (-9.095290e-3 + t * (1.001685e-4 + t * (-1.120083e-6 + t * 6.536332e-9))));
  const double a = 8.24493e-1 + t * (-4.0899e-3 + t * (7.6438e-5 + t * (-8.2467e-7 + t * 5.3875e-9)));
  const double b = -5.72466e-3 + t * (1.0227e-4 + t * -1.6546e-6);
  const double c = 4.8314e-4;
  return rho_w + s * (a + std::sqrt(s) * b + s * c);
}

}  // namespace

double secant_bulk_modulus_eos80_bar(double s, double t, double sea_pressure_dbar) {
  const double p = sea_pressure_dbar / 10.0;  // bar
  const double sqrt_s = std::sqrt(s);
  const double k_w = 19652.21 + t * (148.4206 + t * (-2.327105 + t * (1.360477e-2 + t * -5.155288e-5)));
  const double a_w = 3.239908 + t * (1.43713e-3 + t * (1.16092e-4 + t * -5.77905e-7));
  const double b_w = 8.50935e-5 + t * (-6.12293e-6 + t * 5.2787e-8);
  const double k0 = k_w + s * (54.6746 + t * (-0.603459 + t * (1.09987e-2 + t * -6.1670e-5))) +
                    s * sqrt_s * (7.944e-2 + t * (1.6483e-2 + t * -5.3009e-4));
  const double a = a_w + s * (2.2838e-3 + t * (-1.0981e-5 + t * -1.6078e-6)) + s * sqrt_s * 1.91075e-4;
  const double b = b_w + s * (-9.9348e-7 + t * (2.0816e-8 + t * 9.1697e-10));
  return k0 + p * (a + p * b);
}

double density_eos80(double s, double t, double sea_pressure_dbar) {
  const double p_bar = sea_pressure_dbar / 10.0;
  return density_at_surface(s, t) / (1.0 - p_bar / secant_bulk_modulus_eos80_bar(s, t, sea_pressure_dbar));
}

double sound_speed_unesco(double s, double t, double sea_pressure_dbar) {
  const double p = sea_pressure_dbar / 10.0;  // bar
  const double cw =
      (1402.388 + t * (5.03711 + t * (-5.80852e-2 + t * (3.3420e-4 + t * (-1.47800e-6 + t * 3.1464e-9))))) +
      p * ((0.153563 + t * (6.8982e-4 + t * (-8.1788e-6 + t * (1.3621e-7 + t * -6.1185e-10)))) +
           p * ((3.1260e-5 + t * (-1.7107e-6 + t * (2.5974e-8 + t * (-2.5335e-10 + t * 1.0405e-12)))) +
                p * (-9.7729e-9 + t * (3.8504e-10 + t * -2.3643e-12))));
  const double a =
      (1.389 + t * (-1.262e-2 + t * (7.164e-5 + t * (2.006e-6 + t * -3.21e-8)))) +
      p * ((9.4742e-5 + t * (-1.2580e-5 + t * (-6.4885e-8 + t * (1.0507e-8 + t * -2.0122e-10)))) +
           p * ((-3.9064e-7 + t * (9.1041e-9 + t * (-1.6002e-10 + t * 7.988e-12))) +
                p * (1.100e-10 + t * (6.649e-12 + t * -3.389e-13))));
  const double b = -1.922e-2 + t * -4.42e-5 + p * (7.3637e-5 + t * 1.7945e-7);
  const double d = 1.727e-3 + p * -7.9836e-6;
  return cw + s * (a + std::sqrt(s) * b + s * d);
}

double absorption_francois_garrison_db_per_km(double frequency_hz, double t, double s, double d, double ph) {
  const double f = frequency_hz / 1000.0;  // [kHz]
  const double f2 = f * f;
  const double c = 1412.0 + 3.21 * t + 1.19 * s + 0.0167 * d;
  const double a1 = 8.86 / c * std::pow(10.0, 0.78 * ph - 5.0);
  const double f1 = 2.8 * std::sqrt(s / 35.0) * std::pow(10.0, 4.0 - 1245.0 / (t + 273.0));
  const double a2 = 21.44 * s / c * (1.0 + 0.025 * t);
  const double p2 = 1.0 - 1.37e-4 * d + 6.2e-9 * d * d;
  const double f_mg = 8.17 * std::pow(10.0, 8.0 - 1990.0 / (t + 273.0)) / (1.0 + 0.0018 * (s - 35.0));
  const double p3 = 1.0 - 3.83e-5 * d + 4.9e-10 * d * d;
  const double a3 = t <= 20.0 ? 4.937e-4 - 2.59e-5 * t + 9.11e-7 * t * t - 1.50e-8 * t * t * t
                              : 3.964e-4 - 1.146e-5 * t + 1.45e-7 * t * t - 6.5e-10 * t * t * t;
  return a1 * f1 * f2 / (f1 * f1 + f2) + a2 * p2 * f_mg * f2 / (f_mg * f_mg + f2) + a3 * p3 * f2;
}

}  // namespace hadal::physics

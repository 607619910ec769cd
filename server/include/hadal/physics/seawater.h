// Seawater properties from the UNESCO 1983 algorithms (Fofonoff & Millard, "Algorithms for computation of
// fundamental properties of seawater", UNESCO Tech. Pap. Mar. Sci. 44):
//
//   density_eos80     EOS-80 (UNESCO 1981 international equation of state of seawater):
//                     rho(S, T, p) = rho(S, T, 0) / (1 - p / K(S, T, p)), K the secant bulk modulus
//                     K = K(S, T, 0) + A p + B p^2 (p in bar inside).
//   sound_speed_unesco Chen & Millero (1977) as given in UNESCO 1983, original coefficients.
//   absorption_francois_garrison  sound absorption (Francois & Garrison 1982, J. Acoust. Soc. Am. 72(6),
//                     1879-1890): boric acid and magnesium sulphate relaxations plus pure water's viscosity.
//
// Inputs as in those algorithms: practical salinity S (PSS-78), temperature T on the IPTS-68 scale
// [degC], sea pressure p [dbar] (absolute pressure minus one standard atmosphere; 1 dbar = 1e4 Pa).
// Published check values, reproduced by seawater_test.cc:
//   rho(35, 5, 10000) = 1069.48914 kg/m^3, rho(35, 25, 0) = 1023.34306, rho(0, 5, 0) = 999.96675;
//   c(40, 40, 10000) = 1731.995 m/s, c(35, 20, 0) = 1521.46 m/s (UNESCO 1983 table: 1521.5).
// Modern CTDs report ITS-90 temperatures: convert with its90_to_ipts68 (T68 = 1.00024 T90, Saunders 1990)
// before calling these.
#pragma once

namespace hadal::physics {

// T68 = 1.00024 T90 [degC].
constexpr double its90_to_ipts68(double t90_degc) { return 1.00024 * t90_degc; }

// Density of seawater at sea pressure p [kg/m^3]. Valid for S in [0, 42], T68 in [-2, 40] degC,
// p in [0, 10000] dbar.
double density_eos80(double salinity, double t68_degc, double sea_pressure_dbar);

// Secant bulk modulus K(S, T, p) [bar] of EOS-80 (the p in rho = rho0 / (1 - p/K) is in bar).
double secant_bulk_modulus_eos80_bar(double salinity, double t68_degc, double sea_pressure_dbar);

// Speed of sound in seawater [m/s] (Chen & Millero 1977). Valid for S in [0, 40], T68 in [0, 40] degC,
// p in [0, 10000] dbar.
double sound_speed_unesco(double salinity, double t68_degc, double sea_pressure_dbar);

// Sound absorption in seawater [dB/km], Francois & Garrison (1982), with f in kHz, T in degC, S, depth D
// [m] and pH:
//   alpha = A1 P1 f1 f^2 / (f1^2 + f^2) + A2 P2 f2 f^2 / (f2^2 + f^2) + A3 P3 f^2
//   c  = 1412 + 3.21 T + 1.19 S + 0.0167 D                        (their sound speed approximation)
//   boric acid:  A1 = 8.86 / c 10^(0.78 pH - 5),  P1 = 1,  f1 = 2.8 sqrt(S / 35) 10^(4 - 1245 / (T + 273))
//   MgSO4:       A2 = 21.44 S / c (1 + 0.025 T),  P2 = 1 - 1.37e-4 D + 6.2e-9 D^2,
//                f2 = 8.17 10^(8 - 1990 / (T + 273)) / (1 + 0.0018 (S - 35))
//   pure water:  P3 = 1 - 3.83e-5 D + 4.9e-10 D^2,  A3 = 4.937e-4 - 2.59e-5 T + 9.11e-7 T^2 - 1.50e-8 T^3
//                for T <= 20 degC, else 3.964e-4 - 1.146e-5 T + 1.45e-7 T^2 - 6.5e-10 T^3
// Valid for f in [0.2, 1000] kHz, T in [-2, 22] degC, S in [30, 35], D in [0, 7000] m (their stated ranges;
// the formula is smooth beyond them and sonars use it there, e.g. at full ocean depth).
double absorption_francois_garrison_db_per_km(double frequency_hz, double temperature_degc, double salinity,
                                              double depth_m, double ph = 8.0);

}  // namespace hadal::physics

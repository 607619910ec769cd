// Seawater properties from the UNESCO 1983 algorithms (Fofonoff & Millard, "Algorithms for computation of
// fundamental properties of seawater", UNESCO Tech. Pap. Mar. Sci. 44):
//
//   density_eos80     EOS-80 (UNESCO 1981 international equation of state of seawater):
//                     rho(S, T, p) = rho(S, T, 0) / (1 - p / K(S, T, p)), K the secant bulk modulus
//                     K = K(S, T, 0) + A p + B p^2 (p in bar inside).
//   sound_speed_unesco Chen & Millero (1977) as given in UNESCO 1983, original coefficients.
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

}  // namespace hadal::physics

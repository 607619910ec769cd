// Earth's main magnetic field from a World Magnetic Model coefficient file (WMM2025:
// server/data/WMM2025.COF), for the magnetometer's ideal value and the hadal-geomag tool.
//
// Model (NOAA/BGS, "The US/UK World Magnetic Model for 2025-2030: Technical Report", section 1.2):
//   Potential V(r, phi', lambda, t) = a sum_{n=1..N} (a/r)^(n+1) sum_{m=0..n}
//                                     (g_n^m(t) cos(m lambda) + h_n^m(t) sin(m lambda)) P_n^m(sin phi'),
//   a = 6371200 m (geomagnetic reference radius), N = 12 for WMM2025, P_n^m the Schmidt semi-normalised
//   associated Legendre functions (no Condon-Shortley phase), secular variation linear in time:
//   g_n^m(t) = g_n^m + (t - t0) g_dot_n^m, likewise h; t0 = 2025.0 for WMM2025.
//   1. Geodetic (phi, lambda, h) -> geocentric spherical (r, phi') on WGS84 (a_e = 6378137 m,
//      f = 1/298.257223563, e^2 = f (2 - f)): R_c = a_e / sqrt(1 - e^2 sin^2 phi),
//      p = (R_c + h) cos phi, z = (R_c (1 - e^2) + h) sin phi, r = sqrt(p^2 + z^2), sin phi' = z / r.
//   2. Field in the local geocentric frame (X' north, Y' east, Z' down), B = -grad V:
//      X' = -sum (a/r)^(n+2) sum (g cos m lambda + h sin m lambda) dP_n^m(sin phi')/dphi'
//      Y' =  sum (a/r)^(n+2) sum m (g sin m lambda - h cos m lambda) P_n^m(sin phi') / cos phi'
//      Z' = -sum (n+1) (a/r)^(n+2) sum (g cos m lambda + h sin m lambda) P_n^m(sin phi')
//      and the same sums with g_dot, h_dot for the rates (the field is linear in t).
//   3. Rotation by phi' - phi about the east axis to the geodetic frame:
//      X = X' cos(phi' - phi) - Z' sin(phi' - phi), Y = Y', Z = X' sin(phi' - phi) + Z' cos(phi' - phi).
//   4. H = sqrt(X^2 + Y^2), F = sqrt(H^2 + Z^2), I = atan2(Z, H), D = atan2(Y, X);
//      H_dot = (X X_dot + Y Y_dot) / H, F_dot = (X X_dot + Y Y_dot + Z Z_dot) / F,
//      D_dot = (X Y_dot - Y X_dot) / H^2, I_dot = (H Z_dot - Z H_dot) / F^2 (as the official software).
// Poles: P_n^m = cos^m(phi') Q_n^m(sin phi') with Q_n^m a polynomial, so P_n^m / cos phi' and dP_n^m/dphi'
//   are evaluated from Q_n^m and dQ_n^m/ds without any division by cos phi' (the WMM report's special
//   treatment at +-90 deg, where only m = 1 contributes to Y', falls out of this form). At a pole X and Y
//   are taken along the meridian `longitude_rad` (the limit of the local north/east axes as that meridian
//   reaches the pole), as in the official software; H, Z and F do not depend on the meridian.
//   At H = 0 (a magnetic dip pole) D is atan2(0, 0) = 0 and H_dot, D_dot, I_dot are NaN.
//
// Validity: WMM models are issued for five years from their epoch, [t0, t0 + 5]; field() throws outside
// that span (a scenario's date is checked once at load against valid_from_year / valid_until_year).
// Heights: the report specifies -1 km to 850 km; the potential field continues smoothly below (ocean
// trenches at -11 km) and Hadal uses it there. Geodetic latitude must lie in [-pi/2, pi/2].
//
// Frames: X/Y/Z are the local geodetic north/east/down components; B_ENU_T() gives the same vector in
// the local East-North-Up frame in tesla, the frame Hadal's world W uses at the scenario origin
// (REP-103). Accuracy: synthesis reproduces all 12 official WMM2025 test values within the rounding of
// the printed table (largest deviations 0.050 nT, 0.005 deg, 0.050 nT/yr; geomagnetic_test.cc). The model
// itself (main field only: no crustal or external fields) is good to O(100 nT) and a few tenths of a
// degree in D away from the magnetic poles (the report's error model).
//
// COF file (NOAA layout): a header line "epoch model_name [release_date]", e.g.
//   "    2025.0            WMM-2025     11/13/2024",
// then one row "n m g h g_dot h_dot" (nT, nT/yr) for every 1 <= n <= N, 0 <= m <= n (any order, each
// once, h = h_dot = 0 for m = 0), ended by a line of 9s ("9999...") or the end of the file. N is the
// largest n present, at most kMaxDegree. Errors throw std::runtime_error with "file:line: error: ...".
//
// Cost: one evaluation (position conversion, field and rates) takes ~0.73 us on this machine (Release,
// one core of the 2-core Xeon VM; mean over 10^6 random points, heights -11..0 km, years 2025..2030). The
// recurrence factors of the Legendre functions are tabulated once per process. The magnetometer calls it
// once per sample (a 100 Hz magnetometer: 73 us per simulated second, < 0.01 % of a core); a cache keyed
// on a coarse position/time grid could follow if that ever matters (the field changes by ~0.02 nT per
// metre of height, ~3 F / r, and by up to ~0.3 nT per day).
//
// Thread-safety: immutable after loading; field() is a pure const function.
#pragma once

#include <Eigen/Core>

#include <array>
#include <iosfwd>
#include <string>

namespace hadal::sensors {

// WGS84 ellipsoid.
inline constexpr double kWgs84SemiMajorAxis_m = 6378137.0;
inline constexpr double kWgs84Flattening = 1.0 / 298.257223563;
// Geomagnetic reference radius a of the spherical-harmonic expansion.
inline constexpr double kGeomagneticReferenceRadius_m = 6371200.0;

// Field elements at one point and time. X/Y/Z in the local geodetic frame (north, east, down).
struct GeomagneticElements {
  double x_north_nT = 0.0;
  double y_east_nT = 0.0;
  double z_down_nT = 0.0;
  double h_horizontal_nT = 0.0;  // sqrt(X^2 + Y^2)
  double f_total_nT = 0.0;       // |B|
  double inclination_rad = 0.0;  // I, positive downwards, [-pi/2, pi/2]
  double declination_rad = 0.0;  // D, east of true north, (-pi, pi]

  // Secular variation (yearly rates of the above).
  double x_north_rate_nT_per_yr = 0.0;
  double y_east_rate_nT_per_yr = 0.0;
  double z_down_rate_nT_per_yr = 0.0;
  double h_horizontal_rate_nT_per_yr = 0.0;
  double f_total_rate_nT_per_yr = 0.0;
  double inclination_rate_rad_per_yr = 0.0;
  double declination_rate_rad_per_yr = 0.0;

  // B in the local East-North-Up frame [T]: [Y, X, -Z] * 1e-9.
  Eigen::Vector3d B_ENU_T() const { return 1e-9 * Eigen::Vector3d(y_east_nT, x_north_nT, -z_down_nT); }
  // dB/dt in the local ENU frame [T/yr].
  Eigen::Vector3d B_rate_ENU_T_per_yr() const {
    return 1e-9 * Eigen::Vector3d(y_east_rate_nT_per_yr, x_north_rate_nT_per_yr, -z_down_rate_nT_per_yr);
  }
};

// A spherical-harmonic main-field model (WMM format) up to degree kMaxDegree.
class GeomagneticModel {
 public:
  static constexpr int kMaxDegree = 12;
  // Number of (n, m) pairs for 0 <= m <= n <= kMaxDegree, index n (n + 1) / 2 + m.
  static constexpr int kNumCoefficients = (kMaxDegree + 1) * (kMaxDegree + 2) / 2;

  // Loads a COF file. Throws std::runtime_error "<path>: error: cannot open ..." if it cannot be read,
  // "<path>:<line>: error: ..." for a malformed header or row, a duplicate or out-of-range (n, m), and
  // "<path>: error: missing coefficient n=.. m=.." for an incomplete set.
  static GeomagneticModel load_cof(const std::string& path);
  // The WMM2025 coefficient file hadald uses: $HADAL_DATA_DIR/WMM2025.COF when that variable is set, else
  // the installed copy beside the running executable (<prefix>/share/hadal/WMM2025.COF for
  // <prefix>/bin/hadald, docs/server.md "Installing"), else the source tree's server/data/WMM2025.COF.
  static std::string default_cof_path();
  // Same, from a stream; `source_name` stands for the path in messages.
  static GeomagneticModel parse_cof(std::istream& in, const std::string& source_name);

  // Field at geodetic latitude/longitude [rad], height above the WGS84 ellipsoid [m] and decimal year
  // (e.g. 2027.5 = mid-2027; see decimal_year_from_date). Throws std::domain_error for a non-finite
  // input, |latitude| > pi/2 or a year outside [valid_from_year(), valid_until_year()].
  GeomagneticElements field(double latitude_rad, double longitude_rad, double height_m,
                            double decimal_year) const;

  double epoch_year() const { return epoch_year_; }
  double valid_from_year() const { return epoch_year_; }
  double valid_until_year() const { return epoch_year_ + 5.0; }
  const std::string& name() const { return name_; }                  // e.g. "WMM-2025"
  const std::string& release_date() const { return release_date_; }  // as in the header, may be empty
  int degree() const { return degree_; }

  // Coefficients [nT], [nT/yr]; 1 <= n <= degree(), 0 <= m <= n.
  double g_nT(int n, int m) const { return g_[index(n, m)]; }
  double h_nT(int n, int m) const { return h_[index(n, m)]; }
  double g_rate_nT_per_yr(int n, int m) const { return g_dot_[index(n, m)]; }
  double h_rate_nT_per_yr(int n, int m) const { return h_dot_[index(n, m)]; }

 private:
  static constexpr int index(int n, int m) { return n * (n + 1) / 2 + m; }

  double epoch_year_ = 0.0;
  std::string name_;
  std::string release_date_;
  int degree_ = 0;
  std::array<double, kNumCoefficients> g_{}, h_{}, g_dot_{}, h_dot_{};
};

// Decimal year of a Gregorian calendar date as the official WMM software computes it:
// year + (day_of_year - 1) / (365 or 366), e.g. 2025-07-02 -> 2025.4986 (182 / 365).
// Throws std::invalid_argument for an invalid date.
double decimal_year_from_date(int year, int month, int day);

}  // namespace hadal::sensors

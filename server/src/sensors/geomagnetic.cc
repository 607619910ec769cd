#include "hadal/sensors/geomagnetic.h"
#include "hadal/core/data_dir.h"
#include "hadal/core/units.h"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace hadal::sensors {
namespace {

// Whole-token finite number, or false.
bool parse_double(const std::string& token, double* out) {
  if (token.empty()) return false;
  char* end = nullptr;
  const double x = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size() || !std::isfinite(x)) return false;
  *out = x;
  return true;
}

bool parse_int(const std::string& token, int* out) {
  if (token.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(token.c_str(), &end, 10);
  if (end != token.c_str() + token.size() || errno != 0 || x < -1000000 || x > 1000000) return false;
  *out = static_cast<int>(x);
  return true;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> tokens;
  std::istringstream stream(line);
  for (std::string token; stream >> token;) tokens.push_back(token);
  return tokens;
}

// The end-of-data marker of NOAA COF files: a line of 9s.
bool is_terminator(const std::string& line) {
  const std::string trimmed = line.substr(0, line.find_last_not_of(" \t\r") + 1);
  return trimmed.size() >= 4 && trimmed.find_first_not_of('9') == std::string::npos;
}

// Coefficients of the Legendre recurrences (see field()), independent of the model: computed once.
struct LegendreRecurrence {
  static constexpr int kMax = GeomagneticModel::kMaxDegree;
  static constexpr int kSize = GeomagneticModel::kNumCoefficients;
  std::array<double, kSize> a{}, b{};  // (2n-1)/sqrt(n^2-m^2), sqrt((n-1)^2-m^2)/sqrt(n^2-m^2) at n(n+1)/2+m
  std::array<double, kMax + 1> diagonal{};  // sqrt((2m-1)/(2m)) for m >= 2
  LegendreRecurrence() {
    for (int n = 1; n <= kMax; ++n) {
      for (int m = 0; m < n; ++m) {
        const double k1 = 1.0 / std::sqrt(double(n * n - m * m));
        a[n * (n + 1) / 2 + m] = (2.0 * n - 1.0) * k1;
        b[n * (n + 1) / 2 + m] = std::sqrt(double((n - 1) * (n - 1) - m * m)) * k1;
      }
    }
    for (int m = 2; m <= kMax; ++m) diagonal[m] = std::sqrt((2.0 * m - 1.0) / (2.0 * m));
  }
};

const LegendreRecurrence& legendre_recurrence() {
  static const LegendreRecurrence table;
  return table;
}

[[noreturn]] void fail(const std::string& source, int line, const std::string& message) {
  throw std::runtime_error(source + ":" + std::to_string(line) + ": error: " + message);
}

}  // namespace

std::string GeomagneticModel::default_cof_path() {
  static constexpr const char* kName = "WMM2025.COF";
  // $HADAL_DATA_DIR's as given; an install tree's when it has one; else the source tree's.
  std::error_code error;
  if (const std::optional<DataDir> data = installed_data_dir();
      data && (data->from_environment || std::filesystem::is_regular_file(data->path / kName, error))) {
    return (data->path / kName).string();
  }
  return HADAL_SOURCE_DATA_DIR "/WMM2025.COF";
}

GeomagneticModel GeomagneticModel::load_cof(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    throw std::runtime_error(path + ": error: cannot open geomagnetic coefficient file: " +
                             std::strerror(errno));
  }
  return parse_cof(in, path);
}

GeomagneticModel GeomagneticModel::parse_cof(std::istream& in, const std::string& source_name) {
  GeomagneticModel model;
  std::string line;
  int line_number = 0;

  // Header: epoch, model name, optional release date.
  bool have_header = false;
  while (!have_header && std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string> tokens = split(line);
    if (tokens.empty()) continue;
    if (tokens.size() < 2 || tokens.size() > 3 || !parse_double(tokens[0], &model.epoch_year_)) {
      fail(source_name, line_number,
           "expected the header 'epoch model_name [release_date]' (e.g. '2025.0 WMM-2025 11/13/2024'), got '" +
               line + "'");
    }
    model.name_ = tokens[1];
    if (tokens.size() == 3) model.release_date_ = tokens[2];
    have_header = true;
  }
  if (!have_header) throw std::runtime_error(source_name + ": error: empty geomagnetic coefficient file");

  std::array<int, kNumCoefficients> defined_on_line{};
  while (std::getline(in, line)) {
    ++line_number;
    if (is_terminator(line)) break;
    const std::vector<std::string> tokens = split(line);
    if (tokens.empty()) continue;
    int n = 0, m = 0;
    double values[4];
    bool ok = tokens.size() == 6 && parse_int(tokens[0], &n) && parse_int(tokens[1], &m);
    for (int k = 0; ok && k < 4; ++k) ok = parse_double(tokens[k + 2], &values[k]);
    if (!ok) fail(source_name, line_number, "expected 'n m g h g_dot h_dot' (6 numbers), got '" + line + "'");
    if (n < 1 || n > kMaxDegree || m < 0 || m > n) {
      fail(source_name, line_number,
           "degree/order out of range: n=" + std::to_string(n) + " m=" + std::to_string(m) +
               " (need 1 <= n <= " + std::to_string(kMaxDegree) + ", 0 <= m <= n)");
    }
    const int i = index(n, m);
    if (defined_on_line[i] != 0) {
      fail(source_name, line_number,
           "duplicate coefficient n=" + std::to_string(n) + " m=" + std::to_string(m) + " (first on line " +
               std::to_string(defined_on_line[i]) + ")");
    }
    if (m == 0 && (values[1] != 0.0 || values[3] != 0.0)) {
      fail(source_name, line_number, "h and h_dot must be 0 for m=0 (n=" + std::to_string(n) + ")");
    }
    defined_on_line[i] = line_number;
    model.g_[i] = values[0];
    model.h_[i] = values[1];
    model.g_dot_[i] = values[2];
    model.h_dot_[i] = values[3];
    if (n > model.degree_) model.degree_ = n;
  }
  if (model.degree_ == 0) throw std::runtime_error(source_name + ": error: no coefficients");
  for (int n = 1; n <= model.degree_; ++n) {
    for (int m = 0; m <= n; ++m) {
      if (defined_on_line[index(n, m)] == 0) {
        throw std::runtime_error(source_name + ": error: missing coefficient n=" + std::to_string(n) +
                                 " m=" + std::to_string(m) + " (degree " + std::to_string(model.degree_) +
                                 " needs every 0 <= m <= n <= " + std::to_string(model.degree_) + ")");
      }
    }
  }
  return model;
}

GeomagneticElements GeomagneticModel::field(double latitude_rad, double longitude_rad, double height_m,
                                            double decimal_year) const {
  if (!std::isfinite(latitude_rad) || !std::isfinite(longitude_rad) || !std::isfinite(height_m) ||
      !std::isfinite(decimal_year)) {
    throw std::domain_error("GeomagneticModel::field: non-finite input");
  }
  if (std::abs(latitude_rad) > kPi / 2) {
    throw std::domain_error("GeomagneticModel::field: latitude " + std::to_string(latitude_rad) +
                            " rad outside [-pi/2, pi/2]");
  }
  if (decimal_year < valid_from_year() || decimal_year > valid_until_year()) {
    throw std::domain_error("GeomagneticModel::field: " + name_ + " is valid for " +
                            std::to_string(valid_from_year()) + " to " + std::to_string(valid_until_year()) +
                            " (got " + std::to_string(decimal_year) + ")");
  }

  // 1. Geodetic -> geocentric spherical. sin/cos of phi' straight from (p, z): no asin, exact at the poles.
  const double e2 = kWgs84Flattening * (2.0 - kWgs84Flattening);
  const double sin_lat = std::sin(latitude_rad), cos_lat = std::cos(latitude_rad);
  const double rc = kWgs84SemiMajorAxis_m / std::sqrt(1.0 - e2 * sin_lat * sin_lat);
  const double p = (rc + height_m) * cos_lat;
  const double z = (rc * (1.0 - e2) + height_m) * sin_lat;
  const double r = std::hypot(p, z);
  const double s = z / r;  // sin phi'
  const double c = p / r;  // cos phi' >= 0

  // cos(m lambda), sin(m lambda) by the angle-addition recurrence.
  std::array<double, kMaxDegree + 1> cos_ml{}, sin_ml{};
  cos_ml[0] = 1.0;
  sin_ml[0] = 0.0;
  const double cos_l = std::cos(longitude_rad), sin_l = std::sin(longitude_rad);
  for (int m = 1; m <= degree_; ++m) {
    cos_ml[m] = cos_ml[m - 1] * cos_l - sin_ml[m - 1] * sin_l;
    sin_ml[m] = sin_ml[m - 1] * cos_l + cos_ml[m - 1] * sin_l;
  }
  // cos^m phi'.
  std::array<double, kMaxDegree + 2> cos_pow{};
  cos_pow[0] = 1.0;
  for (int m = 1; m <= degree_ + 1; ++m) cos_pow[m] = cos_pow[m - 1] * c;

  // Schmidt semi-normalised P_n^m(s) = c^m Q_n^m(s):
  //   Q_0^0 = Q_1^1 = 1, Q_n^n = sqrt((2n - 1) / (2n)) Q_{n-1}^{n-1} (n >= 2),
  //   Q_n^m = ((2n - 1) s Q_{n-1}^m - sqrt((n-1)^2 - m^2) Q_{n-2}^m) / sqrt(n^2 - m^2) (n > m),
  // and dQ/ds by differentiating the same recurrence (dQ_m^m = 0).
  const LegendreRecurrence& rec = legendre_recurrence();
  std::array<double, kNumCoefficients> q{}, dq{};
  q[0] = 1.0;
  for (int m = 0; m <= degree_; ++m) {
    const int mm = index(m, m);
    if (m == 1) {
      q[mm] = 1.0;
    } else if (m >= 2) {
      q[mm] = rec.diagonal[m] * q[index(m - 1, m - 1)];
    }
    dq[mm] = 0.0;
    for (int n = m + 1; n <= degree_; ++n) {
      const int i = index(n, m), i1 = index(n - 1, m);
      if (n == m + 1) {
        q[i] = rec.a[i] * s * q[i1];
        dq[i] = rec.a[i] * (q[i1] + s * dq[i1]);
      } else {
        const int i2 = index(n - 2, m);
        q[i] = rec.a[i] * s * q[i1] - rec.b[i] * q[i2];
        dq[i] = rec.a[i] * (q[i1] + s * dq[i1]) - rec.b[i] * dq[i2];
      }
    }
  }

  // 2. Sums in the geocentric frame. For each (n, m):
  //   P = c^m Q, P / c = c^(m-1) Q (m >= 1), dP/dphi' = -m s c^(m-1) Q + c^(m+1) dQ/ds.
  double x_sph = 0.0, y_sph = 0.0, z_sph = 0.0;
  double x_sph_dot = 0.0, y_sph_dot = 0.0, z_sph_dot = 0.0;
  const double dt = decimal_year - epoch_year_;
  const double ratio = kGeomagneticReferenceRadius_m / r;
  double ratio_pow = ratio * ratio;  // (a/r)^(n+2) for n = 0
  for (int n = 1; n <= degree_; ++n) {
    ratio_pow *= ratio;
    double sx = 0.0, sy = 0.0, sz = 0.0, sx_dot = 0.0, sy_dot = 0.0, sz_dot = 0.0;
    for (int m = 0; m <= n; ++m) {
      const int i = index(n, m);
      const double g = g_[i] + dt * g_dot_[i], h = h_[i] + dt * h_dot_[i];
      const double gc_hs = g * cos_ml[m] + h * sin_ml[m];
      const double gs_hc = g * sin_ml[m] - h * cos_ml[m];
      const double gc_hs_dot = g_dot_[i] * cos_ml[m] + h_dot_[i] * sin_ml[m];
      const double gs_hc_dot = g_dot_[i] * sin_ml[m] - h_dot_[i] * cos_ml[m];
      const double p_nm = cos_pow[m] * q[i];
      const double p_over_c = m == 0 ? 0.0 : cos_pow[m - 1] * q[i];
      const double dp = (m == 0 ? 0.0 : -m * s * cos_pow[m - 1] * q[i]) + cos_pow[m + 1] * dq[i];
      sx += gc_hs * dp;
      sy += m * gs_hc * p_over_c;
      sz += gc_hs * p_nm;
      sx_dot += gc_hs_dot * dp;
      sy_dot += m * gs_hc_dot * p_over_c;
      sz_dot += gc_hs_dot * p_nm;
    }
    x_sph -= ratio_pow * sx;
    y_sph += ratio_pow * sy;
    z_sph -= (n + 1) * ratio_pow * sz;
    x_sph_dot -= ratio_pow * sx_dot;
    y_sph_dot += ratio_pow * sy_dot;
    z_sph_dot -= (n + 1) * ratio_pow * sz_dot;
  }

  // 3. Rotate by psi = phi' - phi: cos psi = c cos phi + s sin phi, sin psi = s cos phi - c sin phi.
  const double cos_psi = c * cos_lat + s * sin_lat;
  const double sin_psi = s * cos_lat - c * sin_lat;
  GeomagneticElements e;
  e.x_north_nT = x_sph * cos_psi - z_sph * sin_psi;
  e.y_east_nT = y_sph;
  e.z_down_nT = x_sph * sin_psi + z_sph * cos_psi;
  e.x_north_rate_nT_per_yr = x_sph_dot * cos_psi - z_sph_dot * sin_psi;
  e.y_east_rate_nT_per_yr = y_sph_dot;
  e.z_down_rate_nT_per_yr = x_sph_dot * sin_psi + z_sph_dot * cos_psi;

  // 4. Derived elements and their rates.
  const double x = e.x_north_nT, y = e.y_east_nT, zz = e.z_down_nT;
  const double xd = e.x_north_rate_nT_per_yr, yd = e.y_east_rate_nT_per_yr, zd = e.z_down_rate_nT_per_yr;
  const double h2 = x * x + y * y;
  e.h_horizontal_nT = std::sqrt(h2);
  e.f_total_nT = std::sqrt(h2 + zz * zz);
  e.inclination_rad = std::atan2(zz, e.h_horizontal_nT);
  e.declination_rad = std::atan2(y, x);
  e.h_horizontal_rate_nT_per_yr = (x * xd + y * yd) / e.h_horizontal_nT;
  e.f_total_rate_nT_per_yr = (x * xd + y * yd + zz * zd) / e.f_total_nT;
  e.declination_rate_rad_per_yr = h2 > 0.0 ? (x * yd - y * xd) / h2 : std::nan("");
  e.inclination_rate_rad_per_yr =
      (e.h_horizontal_nT * zd - zz * e.h_horizontal_rate_nT_per_yr) / (e.f_total_nT * e.f_total_nT);
  return e;
}

double decimal_year_from_date(int year, int month, int day) {
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  static constexpr int kDaysInMonth[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (month < 1 || month > 12) {
    throw std::invalid_argument("decimal_year_from_date: month " + std::to_string(month) + " not in 1..12");
  }
  const int days_in_month = kDaysInMonth[month - 1] + (month == 2 && leap ? 1 : 0);
  if (day < 1 || day > days_in_month) {
    throw std::invalid_argument("decimal_year_from_date: day " + std::to_string(day) + " not in 1.." +
                                std::to_string(days_in_month) + " for " + std::to_string(year) + "-" +
                                std::to_string(month));
  }
  int day_of_year = day;
  for (int k = 0; k < month - 1; ++k) day_of_year += kDaysInMonth[k] + (k == 1 && leap ? 1 : 0);
  return year + (day_of_year - 1) / (leap ? 366.0 : 365.0);
}

}  // namespace hadal::sensors

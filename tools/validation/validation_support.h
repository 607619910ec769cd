// Shared by the validation commands (tools/validation/*_main.cc): their command line, JSON numbers,
// output directory, scenario loading with the loader's diagnostics, yaw unwrapping and a small JSON
// object writer. Header-only.
#pragma once

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "hadal/config/scenario_loader.h"
#include "hadal/core/units.h"
#include "cli_args.h"
#include "json_number.h"
#include "parse_number.h"
#include "hadal/core/model.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/triangle_mesh.h"

namespace hadal::validation {

constexpr double kDegPerRad = 180.0 / kPi;

using tools::json_number;
using tools::CommandLine;
using tools::NumberRange;
using tools::parse_number;

// A number rounded to `digits` significant digits (summary values, not round-trip data).
inline std::string json_rounded(double x, int digits = 6) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, x);
  return buf;
}

inline std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// Creates `dir` (and parents) if needed; "" on success, otherwise the reason.
inline std::string ensure_directory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    return dir + ": cannot create the output directory" + (ec ? ": " + ec.message() : "");
  }
  return {};
}

inline std::string join_path(const std::string& dir, const std::string& name) {
  return (std::filesystem::path(dir) / name).string();
}

// Loads a scenario; prints its warnings and errors (file:line:col form) to stderr. Empty on error.
inline std::optional<Model> load_model(const std::string& path, const char* tool) {
  config::LoadResult result = config::load_scenario_file(path);
  for (const config::Diagnostic& d : result.warnings) std::fprintf(stderr, "%s\n", d.format().c_str());
  for (const config::Diagnostic& d : result.errors) std::fprintf(stderr, "%s\n", d.format().c_str());
  if (!result.ok()) {
    std::fprintf(stderr, "%s: %s: the scenario does not load\n", tool, path.c_str());
    return std::nullopt;
  }
  return std::move(result.model);
}

// The first sensor of kind Kind (e.g. sensors::ImuSensor) in the model (vehicle index, sensor index), or
// nothing.
struct SensorRef {
  int vehicle = -1;
  int sensor = -1;
};
template <class Kind>
std::optional<SensorRef> find_sensor(const Model& model) {
  for (std::size_t v = 0; v < model.vehicles.size(); ++v) {
    for (std::size_t k = 0; k < model.vehicles[v].sensors.size(); ++k) {
      if (std::holds_alternative<typename Kind::Spec>(model.vehicles[v].sensors[k].kind)) {
        return SensorRef{static_cast<int>(v), static_cast<int>(k)};
      }
    }
  }
  return std::nullopt;
}

// Progress of a long record on stderr: "tool: name: H of TOTAL h recorded (W s)" each time the sim time
// passes another whole hour (W: wall seconds since construction).
class HourlyProgress {
 public:
  HourlyProgress(const char* tool, std::string name, double hours)
      : tool_(tool), name_(std::move(name)), hours_(hours), start_(std::chrono::steady_clock::now()) {}
  void update(double sim_time_s) {
    if (sim_time_s < next_hour_ * 3600.0) return;
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::fprintf(stderr, "%s: %s: %.0f of %.2f h recorded (%.1f s)\n", tool_, name_.c_str(), next_hour_, hours_, wall);
    next_hour_ += 1.0;
  }

 private:
  const char* tool_;
  std::string name_;
  double hours_;
  std::chrono::steady_clock::time_point start_;
  double next_hour_ = 1.0;  // [h]
};

// One-sided Welch power spectral density of the record x (sample interval dt [s]) with Hann segments of `segment`
// samples overlapping by half, less the record's mean, at the bins b = first..last (frequency b / (segment dt)) by a
// direct DFT at each: psd[b] in x's unit^2 / Hz (zero below first). `segments` gets how many were averaged.
inline std::vector<double> welch_psd(const std::vector<double>& x, double dt, int segment, int first, int last,
                                     int* segments) {
  double mean = 0.0;
  for (double v : x) mean += v / static_cast<double>(x.size());
  std::vector<double> window(static_cast<std::size_t>(segment));
  double window_power = 0.0;
  for (int j = 0; j < segment; ++j) {
    window[j] = 0.5 - 0.5 * std::cos(2.0 * kPi * j / (segment - 1));
    window_power += window[j] * window[j];
  }
  const double fs = 1.0 / dt;
  std::vector<double> psd(static_cast<std::size_t>(last + 1), 0.0);
  int count = 0;
  for (std::size_t start = 0; start + static_cast<std::size_t>(segment) <= x.size(); start += segment / 2, ++count) {
    for (int b = first; b <= last; ++b) {
      std::complex<double> sum = 0.0;
      for (int j = 0; j < segment; ++j) {
        sum += window[j] * (x[start + j] - mean) * std::polar(1.0, -2.0 * kPi * b * j / segment);
      }
      psd[b] += 2.0 * std::norm(sum) / (fs * window_power);
    }
  }
  for (double& p : psd) p /= std::max(count, 1);
  if (segments != nullptr) *segments = count;
  return psd;
}

// A spectrum's CSV: `header`, then per bin b = first..last the frequency b df [Hz] (%.6f) and each column's value at b
// (%.9g). Empty on success, else why not.
inline std::string write_bins_csv(const std::string& path, const std::string& header, double df, int first, int last,
                                  const std::vector<const std::vector<double>*>& columns) {
  std::ofstream out(path);
  out << header << '\n';
  char cell[32];
  for (int b = first; b <= last; ++b) {
    std::snprintf(cell, sizeof(cell), "%.6f", b * df);
    out << cell;
    for (const std::vector<double>* column : columns) {
      std::snprintf(cell, sizeof(cell), ",%.9g", (*column)[static_cast<std::size_t>(b)]);
      out << cell;
    }
    out << '\n';
  }
  out.close();
  return out ? std::string() : path + ": write failed";
}

// The tools' command lines (tools/common/cli_args.h): options "--name value", flags "--name" and -h / --help,
// no positional arguments ("unknown argument 'x'").
inline tools::CommandLine make_command_line(const char* tool, const char* usage) {
  tools::CommandLine command_line(tool, usage);
  command_line.unknown_words("unknown argument '%s'");
  return command_line;
}

// The start of every run: creates the output directory and loads the scenario, reporting problems on
// stderr. Empty on error (exit status 1).
inline std::optional<Model> prepare_run(const std::string& out_dir, const std::string& scenario,
                                        const char* tool) {
  if (const std::string error = ensure_directory(out_dir); !error.empty()) {
    std::fprintf(stderr, "%s: %s\n", tool, error.c_str());
    return std::nullopt;
  }
  return load_model(scenario, tool);
}

// Yaw of B in W (rotation about W's z of the ZYX Euler decomposition) [rad], in (-pi, pi].
inline double yaw_of(const Eigen::Matrix3d& R_WB) { return std::atan2(R_WB(1, 0), R_WB(0, 0)); }
// Tilt of B's z axis from W's vertical [rad].
inline double tilt_of(const Eigen::Matrix3d& R_WB) {
  return std::acos(std::clamp(R_WB(2, 2), -1.0, 1.0));
}

// Continuous angle from successive wrapped samples (each step assumed < pi).
class Unwrapper {
 public:
  double operator()(double wrapped) {
    if (!started_) {
      started_ = true;
      last_ = unwrapped_ = wrapped;
      return unwrapped_;
    }
    double delta = wrapped - last_;
    delta -= 2.0 * kPi * std::round(delta / (2.0 * kPi));
    last_ = wrapped;
    unwrapped_ += delta;
    return unwrapped_;
  }

 private:
  bool started_ = false;
  double last_ = 0.0;
  double unwrapped_ = 0.0;
};

// A vehicle's hydrodynamic mesh in B as Simulation builds it for fluid.model: surface.
inline geometry::TriangleMesh hydrodynamic_mesh_B(const VehicleSpec& spec) {
  return geometry::vehicle_surface_B(spec);
}

// Builds one JSON object, keys in insertion order, pretty-printed with two-space indentation.
class JsonObject {
 public:
  explicit JsonObject(int indent = 0) : indent_(indent) {}
  JsonObject& raw(const std::string& key, const std::string& value) {
    out_ << (first_ ? "" : ",") << "\n" << std::string(indent_ + 2, ' ') << json_string(key) << ": "
         << value;
    first_ = false;
    return *this;
  }
  JsonObject& number(const std::string& key, double value, int digits = 6) {
    return raw(key, json_rounded(value, digits));
  }
  JsonObject& text(const std::string& key, const std::string& value) {
    return raw(key, json_string(value));
  }
  JsonObject& boolean(const std::string& key, bool value) { return raw(key, value ? "true" : "false"); }
  std::string str() const {
    return first_ ? "{}" : "{" + out_.str() + "\n" + std::string(indent_, ' ') + "}";
  }

 private:
  int indent_;
  bool first_ = true;
  std::ostringstream out_;
};

}  // namespace hadal::validation

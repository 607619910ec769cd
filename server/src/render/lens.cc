#include "hadal/render/lens.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "hadal/core/units.h"
#include "hadal/core/validation_error.h"

namespace hadal::render {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Newton stops when the distorted point is reproduced to this many pixels (header: below 1e-9 px).
constexpr double kResidualPx = 1e-10;
constexpr int kMaxNewtonIterations = 50;

std::string number(double x) {
  std::ostringstream out;
  out.precision(10);
  out << x;
  return out.str();
}

using validation::invalid;

// Plumb bob: the radial polynomial and its derivative in r² (header).
double radial(const LensSpec& l, double r2) {
  const auto& d = l.distortion;
  return 1.0 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
}
double radial_d_r2(const LensSpec& l, double r2) {
  const auto& d = l.distortion;
  return d[0] + r2 * (2.0 * d[1] + 3.0 * r2 * d[4]);
}

// Plumb bob's radial map r -> r radial(r²) (the distorted radius when p1 = p2 = 0) and its derivative.
double radial_map(const LensSpec& l, double r) { return r * radial(l, r * r); }
double radial_map_derivative(const LensSpec& l, double r) {
  return radial(l, r * r) + 2.0 * r * r * radial_d_r2(l, r * r);
}

// Equidistant: θ_d(θ) and its derivative.
double theta_d(const LensSpec& l, double theta) {
  const auto& k = l.distortion;
  const double t2 = theta * theta;
  return theta * (1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
}
double theta_d_derivative(const LensSpec& l, double theta) {
  const auto& k = l.distortion;
  const double t2 = theta * theta;
  return 1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])));
}

// The radial map's monotone range [0, limit): r -> r radial(r²) (plumb bob, r up to 1e4, i.e. 89.99°) or
// θ -> θ_d(θ) (equidistant, θ up to π), up to the first point where its derivative stops being positive.
// A fine grid (geometric for plumb bob) finds the first sign change, bisection refines it.
double monotone_limit(const LensSpec& l) {
  const bool fisheye = l.model == LensModel::kEquidistant;
  const auto derivative = [&](double s) {
    return fisheye ? theta_d_derivative(l, s) : radial_map_derivative(l, s);
  };
  const int n = 4096;
  const double s_max = fisheye ? kPi : 1e4;
  double previous = 0.0;
  for (int i = 1; i <= n; ++i) {
    const double s = fisheye ? s_max * i / n : 1e-4 * std::pow(1e8, static_cast<double>(i) / n);
    if (!(derivative(s) > 0.0)) {
      double lo = previous, hi = s;
      for (int j = 0; j < 100; ++j) {
        const double mid = 0.5 * (lo + hi);
        (derivative(mid) > 0.0 ? lo : hi) = mid;
      }
      return lo;
    }
    previous = s;
  }
  return fisheye ? kPi : kInf;
}

// Solves map(s) = target for s in [0, limit) with map increasing there: bisection to a bracket, Newton to
// polish. False when the target lies beyond the monotone range.
template <typename Map, typename Derivative>
bool invert_monotone(Map map, Derivative derivative, double target, double limit, double* s) {
  double lo = 0.0;
  double hi = std::isfinite(limit) ? limit : 1.0;
  if (!std::isfinite(limit)) {
    while (map(hi) < target) {
      hi *= 2.0;
      if (hi > 1e12) return false;
    }
  } else if (!(map(hi) > target)) {
    return false;
  }
  for (int i = 0; i < 200 && hi - lo > 1e-15 * std::max(1.0, hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    (map(mid) < target ? lo : hi) = mid;
  }
  double x = 0.5 * (lo + hi);
  for (int i = 0; i < 3; ++i) {
    const double step = (map(x) - target) / derivative(x);
    const double next = x - step;
    if (next >= lo && next <= hi) x = next;
  }
  *s = x;
  return true;
}

// Plumb bob: the distorted point and the Jacobian of (x_d, y_d) with respect to (x, y).
Eigen::Vector2d plumb_bob(const LensSpec& l, const Eigen::Vector2d& p, Eigen::Matrix2d* J) {
  const double x = p.x(), y = p.y();
  const double p1 = l.distortion[2], p2 = l.distortion[3];
  const double r2 = x * x + y * y;
  const double rad = radial(l, r2);
  if (J != nullptr) {
    const double dR = radial_d_r2(l, r2);
    const double cross = 2.0 * x * y * dR + 2.0 * p1 * x + 2.0 * p2 * y;
    *J << rad + 2.0 * x * x * dR + 2.0 * p1 * y + 6.0 * p2 * x, cross,
        cross, rad + 2.0 * y * y * dR + 6.0 * p1 * y + 2.0 * p2 * x;
  }
  return {x * rad + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
          y * rad + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

// The inversion of one pixel, given the lens's monotone limit (monotone_limit()).
bool pixel_ray(const LensSpec& l, double limit, const Eigen::Vector2d& uv, Eigen::Vector3d* d_C) {
  const Eigen::Vector2d xd((uv.x() - l.cx) / l.fx, (uv.y() - l.cy) / l.fy);
  const double rd = xd.norm();
  switch (l.model) {
    case LensModel::kPinhole:
      *d_C = Eigen::Vector3d(xd.x(), xd.y(), 1.0).normalized();
      return true;
    case LensModel::kEquidistant: {
      if (rd == 0.0) {
        *d_C = Eigen::Vector3d::UnitZ();
        return true;
      }
      double theta = 0.0;
      if (!invert_monotone([&](double t) { return theta_d(l, t); },
                           [&](double t) { return theta_d_derivative(l, t); }, rd, limit, &theta)) {
        return false;
      }
      const double s = std::sin(theta) / rd;
      *d_C = Eigen::Vector3d(s * xd.x(), s * xd.y(), std::cos(theta));
      return true;
    }
    case LensModel::kRadialTangential: {
      // Start from the radial-only inverse (exact when p1 = p2 = 0), then 2-D Newton with the tangential
      // terms; the solution must stay inside the monotone radius with an orientation-preserving Jacobian.
      Eigen::Vector2d p = xd;
      if (rd > 0.0) {
        double r = 0.0;
        if (!invert_monotone([&](double s) { return radial_map(l, s); },
                             [&](double s) { return radial_map_derivative(l, s); }, rd, limit, &r)) {
          return false;
        }
        p = xd * (r / rd);
      }
      const Eigen::Vector2d scale(l.fx, l.fy);
      Eigen::Matrix2d J;
      bool converged = false;
      for (int i = 0; i < kMaxNewtonIterations; ++i) {
        const Eigen::Vector2d residual = plumb_bob(l, p, &J) - xd;
        if (residual.cwiseProduct(scale).cwiseAbs().maxCoeff() < kResidualPx) {
          converged = true;
          break;
        }
        if (!(J.determinant() > 0.0)) return false;
        p -= J.partialPivLu().solve(residual);
        if (!p.allFinite()) return false;
      }
      if (!converged) return false;
      plumb_bob(l, p, &J);
      if (!(J.determinant() > 0.0) || !(p.norm() < limit)) return false;
      *d_C = Eigen::Vector3d(p.x(), p.y(), 1.0).normalized();
      return true;
    }
  }
  return false;
}

}  // namespace

std::string_view to_string(LensModel model) {
  switch (model) {
    case LensModel::kPinhole: return "pinhole";
    case LensModel::kRadialTangential: return "radial_tangential";
    case LensModel::kEquidistant: return "equidistant";
  }
  return "?";
}

bool lens_model_from_string(std::string_view name, LensModel* model) {
  for (LensModel m : {LensModel::kPinhole, LensModel::kRadialTangential, LensModel::kEquidistant}) {
    if (name == to_string(m)) {
      *model = m;
      return true;
    }
  }
  return false;
}

LensSpec lens_from_horizontal_fov(int width_px, int height_px, double hfov_rad) {
  if (!(hfov_rad > 0.0 && hfov_rad < kPi)) invalid("hfov", "must be in (0, 180) deg (got " + number(to_degrees(hfov_rad)) + " deg)");
  LensSpec lens;
  lens.width_px = width_px;
  lens.height_px = height_px;
  lens.fx = 0.5 * width_px / std::tan(0.5 * hfov_rad);
  lens.fy = lens.fx;
  lens.cx = 0.5 * (width_px - 1);
  lens.cy = 0.5 * (height_px - 1);
  return lens;
}

Eigen::Vector2d distort(const LensSpec& lens, const Eigen::Vector2d& xy) {
  switch (lens.model) {
    case LensModel::kPinhole: return xy;
    case LensModel::kRadialTangential: return plumb_bob(lens, xy, nullptr);
    case LensModel::kEquidistant: {
      const double r = xy.norm();
      if (r == 0.0) return xy;
      return xy * (theta_d(lens, std::atan(r)) / r);
    }
  }
  return xy;
}

bool project(const LensSpec& lens, const Eigen::Vector3d& p_C, Eigen::Vector2d* uv_px) {
  Eigen::Vector2d xd;
  if (lens.model == LensModel::kEquidistant) {
    const double r = p_C.head<2>().norm();
    const double theta = std::atan2(r, p_C.z());
    if (r == 0.0) {
      if (!(p_C.z() > 0.0)) return false;
      xd.setZero();
    } else {
      if (!(theta < kPi)) return false;
      xd = p_C.head<2>() * (theta_d(lens, theta) / r);
    }
  } else {
    if (!(p_C.z() > 0.0)) return false;
    xd = distort(lens, p_C.head<2>() / p_C.z());
  }
  *uv_px = Eigen::Vector2d(lens.fx * xd.x() + lens.cx, lens.fy * xd.y() + lens.cy);
  return uv_px->allFinite();
}

bool pixel_ray_C(const LensSpec& lens, const Eigen::Vector2d& uv_px, Eigen::Vector3d* d_C) {
  return pixel_ray(lens, monotone_limit(lens), uv_px, d_C);
}

Lens make_lens(const LensSpec& spec) {
  if (spec.width_px < 1 || spec.width_px > 16384) invalid("width", "must be in [1, 16384] px (got " + std::to_string(spec.width_px) + ")");
  if (spec.height_px < 1 || spec.height_px > 16384) invalid("height", "must be in [1, 16384] px (got " + std::to_string(spec.height_px) + ")");
  if (!(spec.fx > 0.0) || !std::isfinite(spec.fx)) invalid("fx", "must be a positive focal length in px (got " + number(spec.fx) + ")");
  if (!(spec.fy > 0.0) || !std::isfinite(spec.fy)) invalid("fy", "must be a positive focal length in px (got " + number(spec.fy) + ")");
  if (!std::isfinite(spec.cx)) invalid("cx", "must be finite");
  if (!std::isfinite(spec.cy)) invalid("cy", "must be finite");
  for (double c : spec.distortion) {
    if (!std::isfinite(c)) invalid("distortion", "coefficients must be finite");
  }
  if (spec.model == LensModel::kEquidistant && spec.distortion[4] != 0.0) {
    invalid("distortion", "the equidistant model has four coefficients k1..k4");
  }
  if (spec.model == LensModel::kPinhole &&
      std::any_of(spec.distortion.begin(), spec.distortion.end(), [](double c) { return c != 0.0; })) {
    invalid("distortion", "a pinhole lens has no distortion coefficients");
  }

  Lens lens;
  lens.spec_ = spec;
  const double limit = monotone_limit(spec);
  lens.rays_C_.resize(static_cast<std::size_t>(spec.width_px) * spec.height_px);
  for (int v = 0; v < spec.height_px; ++v) {
    for (int u = 0; u < spec.width_px; ++u) {
      Eigen::Vector3d d;
      const Eigen::Vector2d uv(u, v);
      if (!pixel_ray(spec, limit, uv, &d)) {
        invalid("distortion", "the " + std::string(to_string(spec.model)) + " distortion has no inverse at pixel (" +
                                  std::to_string(u) + ", " + std::to_string(v) +
                                  "): the lens folds over inside the image (monotone up to " +
                                  (spec.model == LensModel::kEquidistant ? "theta = " + number(to_degrees(limit)) + " deg"
                                                                         : "r = " + number(limit)) +
                                  "); check the coefficients' signs and the image size");
      }
      lens.rays_C_[static_cast<std::size_t>(v) * spec.width_px + u] = d.cast<float>();
    }
  }
  // The check reads the finished table back in a pass of its own: checking each ray right after storing
  // it let GCC 12 at -O3 forward the unrounded double to the projection (x and y of the Vector3f, seen
  // in this module's test), which would check a ray the renderer never uses.
  double worst = 0.0;
  for (int v = 0; v < spec.height_px; ++v) {
    for (int u = 0; u < spec.width_px; ++u) {
      const Eigen::Vector3d d = lens.ray_C(u, v).cast<double>();
      Eigen::Vector2d back;
      if (!project(spec, d, &back)) {
        invalid("distortion", "the ray of pixel (" + std::to_string(u) + ", " + std::to_string(v) +
                                  ") does not project back into the image");
      }
      worst = std::max(worst, (back - Eigen::Vector2d(u, v)).cwiseAbs().maxCoeff());
    }
  }
  lens.max_reprojection_error_px_ = worst;
  return lens;
}

std::string Lens::distortion_model() const {
  return spec_.model == LensModel::kEquidistant ? "equidistant" : "plumb_bob";
}

std::vector<double> Lens::D() const {
  if (spec_.model == LensModel::kEquidistant) return {spec_.distortion.begin(), spec_.distortion.begin() + 4};
  return {spec_.distortion.begin(), spec_.distortion.end()};
}

std::array<double, 9> Lens::K() const {
  return {spec_.fx, 0.0, spec_.cx, 0.0, spec_.fy, spec_.cy, 0.0, 0.0, 1.0};
}

std::array<double, 9> Lens::R() const { return {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}; }

std::array<double, 12> Lens::P() const {
  return {spec_.fx, 0.0, spec_.cx, 0.0, 0.0, spec_.fy, spec_.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
}

}  // namespace hadal::render

// Forward-scatter blur (docs/ARCHITECTURE.md, "Cameras"): light leaving a surface that the water
// scatters through a small angle on its way to the camera still arrives, from a direction a little off
// the surface point's, and spreads a faint halo around everything bright.
//
// Model (single small-angle scattering on the camera side of the path; units: angles [rad], lengths
// [m], coefficients [1/m]):
//   forward share       F = the Henyey–Greenstein phase function's share within theta_max of the
//                       forward direction (closed form, hg_fraction_within), b_f = F b per channel.
//   energy              a surface point of radiance L at distance d sends L exp(-c d) straight to the
//                       camera (the unscattered beam, as before) and L exp(-c d) (exp(b_f d) - 1)
//                       scattered within theta_max: light scattered forward is redirected, not lost,
//                       so the two sum to L exp(-(c - b_f) d) (McGlamery's and Jaffe's exp(-G R) with
//                       G = c - b_f).
//   apparent angle      a scattering through theta at distance s from the camera shows the point
//                       alpha = theta (d - s) / d off its true direction (small angles); with the
//                       scattering uniform along the path, u = (d - s) / d is uniform in [0, 1], and
//                       the point spread over alpha is independent of d:
//                         K(alpha) = int_0^1 u^-2 P(alpha / u) du = (1 / alpha) int_alpha^theta_max P(theta) dtheta [1/sr]
//                       with P(theta) = p_HG(cos theta) sin(theta) / (theta F) the scattering angle's
//                       density on the small-angle plane (int_0^theta_max P 2 pi theta dtheta = 1), so
//                       int K 2 pi alpha dalpha = 1; encircled energy
//                         E(alpha) = 2 pi (int_0^alpha theta P dtheta + alpha int_alpha^theta_max P dtheta).
// Not modelled: forward scattering on the light's side of the path (the beams' irradiance), multiple
// scattering (the spread widening with optical depth: keep b_f d below ~1), light from outside the field
// of view, backscatter and marine snow (not blurred).
//
// On the image the spread is a convolution with K in pixels (alpha = |(du / fx, dv / fy)|, the lens's
// focal lengths; distortion's change of scale across the image is ignored), done on blocks of s x s
// px, s = 2, 4, 8, ...: r < 6 px on 2 px blocks, then each ring r in [1.5 s, 3 s) px on blocks of s
// (block sums convolved with the ring's block weights, interpolated bilinearly to the next finer
// level's blocks, coarsest first, and from 2 px blocks to the pixels): ~20 multiply-adds a pixel and
// channel whatever theta_max. The block weights are exact for light spread uniformly over a block; the
// interpolation moves light by a fraction of a block, so a point's encircled energy stays within
// ~0.035 of E (forward_scatter_test.cc), and detail of the spread under ~2 px is smoothed.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "hadal/core/parallel_for.h"
#include "hadal/render/optics.h"

namespace hadal::render {

// The share of the Henyey–Greenstein phase function p(cos psi) within max_angle_rad of forward:
// int_{cos max}^1 2 pi p dmu = (1 - g^2) / (2 g) (1 / (1 - g) - 1 / sqrt(1 + g^2 - 2 g cos max)),
// (1 - cos max) / 2 for g = 0. max_angle_rad in [0, pi].
double hg_fraction_within(double g, double max_angle_rad);

// b_f = b F per channel [1/m]; zero when water.forward_scatter_max_angle_rad is 0.
Rgb forward_scattering_per_m(const WaterOptics& water);

// The point spread K(alpha) and its encircled energy E(alpha) (header formulas) for phase g and
// theta_max, tabulated once (2048 intervals, trapezoid rule; E(theta_max) = 1 by construction).
class ForwardScatterPsf {
 public:
  ForwardScatterPsf(double g, double max_angle_rad);  // max_angle_rad in (0, pi / 6]
  double max_angle_rad() const { return max_angle_rad_; }
  double density_per_sr(double alpha_rad) const;  // K; +inf at 0, 0 beyond theta_max
  double encircled(double alpha_rad) const;       // E, 0 at 0, 1 from theta_max on

 private:
  double tail(double alpha_rad) const;  // int_alpha^theta_max P dtheta
  double max_angle_rad_;
  double step_rad_;
  std::vector<double> q_;  // int_0^theta P dtheta at theta = k step
  std::vector<double> m_;  // int_0^theta theta' P dtheta' at theta = k step
};

// The point spread in pixels for a lens of focal lengths fx, fy [px], at the scales of the header.
struct ForwardScatterKernel {
  struct Level {
    int block_px = 1;                 // s
    int reach = 0;                    // block offsets -reach..reach in x and y
    std::vector<double> weight;       // (2 reach + 1)^2, row-major by dy then dx: share of a block's light
                                      // landing in the block (dx, dy) away
  };
  std::vector<Level> levels;  // block 1 first; the weights of all levels sum to 1
};
ForwardScatterKernel make_forward_scatter_kernel(const ForwardScatterPsf& psf, double fx_px, double fy_px);

// The kernel for this water's phase g and theta_max and these focal lengths, made once and kept for
// the run (the last 16 made; thread-safe): a camera's frames share it.
std::shared_ptr<const ForwardScatterKernel> forward_scatter_kernel(const WaterOptics& water, double fx_px, double fy_px);

// Adds the spread of `source` (R, G and B planes of width x height, row-major; per pixel the radiance to spread, i.e. the
// surface's radiance at the camera times exp(b_f d) - 1) to `radiance`. Rows in parallel tasks;
// deterministic whatever the threads.
void add_forward_scatter(const ForwardScatterKernel& kernel, int width, int height,
                         const std::array<std::vector<float>, 3>& source, std::vector<Eigen::Array3f>& radiance,
                         const ParallelFor& parallel = serial_for);

}  // namespace hadal::render

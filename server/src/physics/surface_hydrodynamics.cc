#include "hadal/physics/surface_hydrodynamics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/triangle_mesh.h"

// The hot loops are compiled twice, for x86-64-v3 (AVX2 + FMA, 8 float lanes) and for the baseline
// (SSE2, 4 lanes), and the loader picks one at run time (GCC function multiversioning): the build
// stays portable without -march flags.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define HADAL_HOT_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define HADAL_HOT_CLONES
#endif

namespace hadal::physics {

namespace {

constexpr std::size_t kLanes = SurfaceHydrodynamics::kLanes;
constexpr std::size_t kBlock = SurfaceHydrodynamics::kBlock;

// 1/sqrt(x) for x >= 0 by the bit-level initial guess and three Newton steps (relative error
// 3.4e-2 -> 1.8e-3 -> 4.6e-6 -> 3e-11, i.e. float rounding). Plain arithmetic, so it vectorises:
// std::sqrt does not under the default -fmath-errno (GCC guards it with a branch to the library
// call, and neither `#pragma GCC optimize` nor the attribute lifts that for a target clone).
// x = 0 gives a large finite value (~1.3e19), so x * rsqrt(x) = 0 exactly and no NaN appears.
inline float rsqrt_newton(float x) {
#if defined(__GNUC__)
  float y = __builtin_bit_cast(float, 0x5f375a86u - (__builtin_bit_cast(std::uint32_t, x) >> 1));
#else
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits = 0x5f375a86u - (bits >> 1);
  float y;
  std::memcpy(&y, &bits, sizeof y);
#endif
  const float half_x = 0.5f * x;
  y = y * (1.5f - half_x * y * y);
  y = y * (1.5f - half_x * y * y);
  y = y * (1.5f - half_x * y * y);
  return y;
}

// Per-step constants of the face loop, in float.
struct KernelParams {
  float R[9];     // R_WB, row-major
  float t[3];     // R_WB p_BBcm offset: r = R c_B + t (offset of a B point from p_WBcm, W axes)
  float v[3];     // v_WBcm
  float w[3];     // w_WB
  float drag;     // 1/2 C_D
  float friction; // 1/2 C_f
  float lift;     // 1/2 C_L
  float magnus;   // C_M
  float buoyancy; // 1 or 0
  float g;        // gravity magnitude (0 if buoyancy is off)
  float up_B[3];  // z_W expressed in B (third row of R_WB); with waves z_W - grad p_d / (rho g)
  float p_ref;    // gauge pressure at p_WBcm, or 0 for a fully submerged body [Pa]
};

// Offsets r = R c_B + t of a block of centroids (W axes, from the centre of mass).
HADAL_HOT_CLONES
void transform_centroids(const float* __restrict cx, const float* __restrict cy,
                         const float* __restrict cz, std::size_t n, const KernelParams& k,
                         float* __restrict rx, float* __restrict ry, float* __restrict rz) {
  const float R0 = k.R[0], R1 = k.R[1], R2 = k.R[2], R3 = k.R[3], R4 = k.R[4], R5 = k.R[5],
              R6 = k.R[6], R7 = k.R[7], R8 = k.R[8];
  const float t0 = k.t[0], t1 = k.t[1], t2 = k.t[2];
  for (std::size_t i = 0; i < n; ++i) {
    rx[i] = R0 * cx[i] + R1 * cy[i] + R2 * cz[i] + t0;
    ry[i] = R3 * cx[i] + R4 * cy[i] + R5 * cz[i] + t1;
    rz[i] = R6 * cx[i] + R7 * cy[i] + R8 * cz[i] + t2;
  }
}

// Sums of one block into kLanes independent float accumulators per wrench component (kept apart so
// the loop vectorises without reassociating a single sum). mask[i] is 1 (wet) or 0.
// n is a multiple of kLanes.
struct LaneSums {
  alignas(64) float f[6][kLanes];  // fx fy fz tx ty tz
  alignas(64) float area[kLanes];
};

HADAL_HOT_CLONES
void face_forces(const float* __restrict A, const float* __restrict nbx,
                 const float* __restrict nby, const float* __restrict nbz,
                 const float* __restrict mask, const float* __restrict exposed,
                 const float* __restrict rx,
                 const float* __restrict ry, const float* __restrict rz,
                 const float* __restrict rho, const float* __restrict dp,
                 const float* __restrict ux, const float* __restrict uy,
                 const float* __restrict uz, const float* __restrict sxx,
                 const float* __restrict syy, const float* __restrict szz,
                 const float* __restrict sxy, const float* __restrict sxz,
                 const float* __restrict syz, std::size_t n, const KernelParams& k,
                 LaneSums& __restrict s) {
  const float R0 = k.R[0], R1 = k.R[1], R2 = k.R[2], R3 = k.R[3], R4 = k.R[4], R5 = k.R[5],
              R6 = k.R[6], R7 = k.R[7], R8 = k.R[8];
  const float vx = k.v[0], vy = k.v[1], vz = k.v[2];
  const float wx = k.w[0], wy = k.w[1], wz = k.w[2];
  const float kd = k.drag, kf = k.friction, kl = k.lift, km = k.magnus, kb = k.buoyancy;
  const float p_ref = k.p_ref;
  const float gk = k.g, gx = k.up_B[0], gy = k.up_B[1], gz = k.up_B[2];
  for (std::size_t i0 = 0; i0 < n; i0 += kLanes) {
    for (std::size_t j = 0; j < kLanes; ++j) {
      const std::size_t i = i0 + j;
      const float a = A[i] * mask[i];
      const float nx = R0 * nbx[i] + R1 * nby[i] + R2 * nbz[i];
      const float ny = R3 * nbx[i] + R4 * nby[i] + R5 * nbz[i];
      const float nz = R6 * nbx[i] + R7 * nby[i] + R8 * nbz[i];
      const float px = rx[i], py = ry[i], pz = rz[i];
      // Relative flow v_c = u - (v + w x r).
      const float cx = ux[i] - (vx + wy * pz - wz * py);
      const float cy = uy[i] - (vy + wz * px - wx * pz);
      const float cz = uz[i] - (vz + wx * py - wy * px);
      const float cn = nx * cx + ny * cy + nz * cz;
      const float vv = cx * cx + cy * cy + cz * cz;
      const float inv_v = rsqrt_newton(vv);  // 1/|v_c| (large and harmless when v_c = 0)
      const float vmag = vv * inv_v;
      // |v_t|^2 = |v_c|^2 - c_n^2 >= 0 up to rounding; fabs instead of max(., 0) keeps the loop
      // free of selects that GCC would turn into branches (it may not speculate FP ops that could
      // trap under the default -ftrapping-math); the difference is O(eps |v_c|^2).
      const float vt2 = std::fabs(vv - cn * cn);
      const float vt = vt2 * rsqrt_newton(vt2);
      const float cneg = 0.5f * (cn - std::fabs(cn));  // min(c_n, 0): the facing-flow mask
      const float ra = rho[i] * a;  // ra: rho A for wet faces, 0 otherwise
      const float re = ra * exposed[i];  // flow terms only on faces the flow reaches
      // F = n * s_n + v_c * s_v - km rho A |v_c| (w x v_c).
      const float s_n = -kb * (p_ref + dp[i]) * a + re * (-kd * cneg * cneg - kf * vt * cn +
                                                          kl * cn * vmag);
      const float s_v = re * (kf * vt - kl * cn * cn * inv_v);
      const float s_m = -km * re * vmag;  // Magnus along w x (-v_c): see the header
      const float fx = nx * s_n + cx * s_v + s_m * (wy * cz - wz * cy);
      const float fy = ny * s_n + cy * s_v + s_m * (wz * cx - wx * cz);
      const float fz = nz * s_n + cz * s_v + s_m * (wx * cy - wy * cx);
      s.f[0][j] += fx;
      s.f[1][j] += fy;
      s.f[2][j] += fz;
      // Centre-of-pressure moment rho g A (C_W z) x n, with C_W z = R (C_B up_B).
      const float qx = sxx[i] * gx + sxy[i] * gy + sxz[i] * gz;
      const float qy = sxy[i] * gx + syy[i] * gy + syz[i] * gz;
      const float qz = sxz[i] * gx + syz[i] * gy + szz[i] * gz;
      const float Qx = R0 * qx + R1 * qy + R2 * qz;
      const float Qy = R3 * qx + R4 * qy + R5 * qz;
      const float Qz = R6 * qx + R7 * qy + R8 * qz;
      const float kp = gk * ra;
      s.f[3][j] += py * fz - pz * fy + kp * (Qy * nz - Qz * ny);
      s.f[4][j] += pz * fx - px * fz + kp * (Qz * nx - Qx * nz);
      s.f[5][j] += px * fy - py * fx + kp * (Qx * ny - Qy * nx);
      s.area[j] += a;
    }
  }
}

// Waterline classification: wet[i] = 1 if all three vertices are at or below the surface, else 0;
// cross[i] = 1 if the face has vertices strictly on both sides (it is clipped). h(x_B) = h0 + g . x_B
// is the height of a B point above the surface. Float is enough: a body near the surface has small
// h0, and a body far from it never gets here (bounding-sphere test).
HADAL_HOT_CLONES
void classify(const float* const* v, std::size_t n, float h0, float gx, float gy, float gz,
              float* __restrict wet, float* __restrict cross) {
  const float *__restrict ax = v[0], *__restrict ay = v[1], *__restrict az = v[2];
  const float *__restrict bx = v[3], *__restrict by = v[4], *__restrict bz = v[5];
  const float *__restrict cx = v[6], *__restrict cy = v[7], *__restrict cz = v[8];
  for (std::size_t i = 0; i < n; ++i) {
    const float h_a = h0 + gx * ax[i] + gy * ay[i] + gz * az[i];
    const float h_b = h0 + gx * bx[i] + gy * by[i] + gz * bz[i];
    const float h_c = h0 + gx * cx[i] + gy * cy[i] + gz * cz[i];
    const bool all_wet = (h_a <= 0.0f) & (h_b <= 0.0f) & (h_c <= 0.0f);
    const bool any_wet = (h_a < 0.0f) | (h_b < 0.0f) | (h_c < 0.0f);
    const bool any_dry = (h_a > 0.0f) | (h_b > 0.0f) | (h_c > 0.0f);
    wet[i] = all_wet ? 1.0f : 0.0f;
    cross[i] = any_wet & any_dry ? 1.0f : 0.0f;
  }
}

void pad(HydroFaces& f) {
  const std::size_t n = (f.area.size() + kLanes - 1) / kLanes * kLanes;
  for (auto* a : {&f.area, &f.n_x, &f.n_y, &f.n_z, &f.c_x, &f.c_y, &f.c_z, &f.s_xx, &f.s_yy,
                  &f.s_zz, &f.s_xy, &f.s_xz, &f.s_yz, &f.exposed}) a->resize(n, 0.0f);
}

void clear(HydroFaces& f) {
  for (auto* a : {&f.area, &f.n_x, &f.n_y, &f.n_z, &f.c_x, &f.c_y, &f.c_z, &f.s_xx, &f.s_yy,
                  &f.s_zz, &f.s_xy, &f.s_xz, &f.s_yz, &f.exposed}) a->clear();
}

void push_face(HydroFaces& f, double area, const Eigen::Vector3d& n, const Eigen::Vector3d& c,
               const Eigen::Matrix3d& C, float exposed) {
  f.exposed.push_back(exposed);
  f.s_xx.push_back(static_cast<float>(C(0, 0)));
  f.s_yy.push_back(static_cast<float>(C(1, 1)));
  f.s_zz.push_back(static_cast<float>(C(2, 2)));
  f.s_xy.push_back(static_cast<float>(C(0, 1)));
  f.s_xz.push_back(static_cast<float>(C(0, 2)));
  f.s_yz.push_back(static_cast<float>(C(1, 2)));
  f.area.push_back(static_cast<float>(area));
  f.n_x.push_back(static_cast<float>(n.x()));
  f.n_y.push_back(static_cast<float>(n.y()));
  f.n_z.push_back(static_cast<float>(n.z()));
  f.c_x.push_back(static_cast<float>(c.x()));
  f.c_y.push_back(static_cast<float>(c.y()));
  f.c_z.push_back(static_cast<float>(c.z()));
}

}  // namespace

double UniformWater::gauge_pressure(double z_W) const {
  return density * gravity * std::max(surface_z - z_W, 0.0);
}

void UniformWater::sample(const Eigen::Vector3d& origin_W, std::size_t n, const float* dx,
                          const float* dy, const float* dz, const FluidSamples& out) const {
  (void)dx;
  (void)dy;
  const float rho = static_cast<float>(density);
  const float rho_g = static_cast<float>(density * gravity);
  const float d0 = static_cast<float>(surface_z - origin_W.z());  // depth of the origin
  const float ux = static_cast<float>(current_W.x()), uy = static_cast<float>(current_W.y()),
              uz = static_cast<float>(current_W.z());
  for (std::size_t i = 0; i < n; ++i) {
    const float d = d0 - dz[i];
    // Both below the surface: the exact difference -rho g dz (no cancellation of d0 at depth).
    const float both = -rho_g * dz[i];
    const float general = rho_g * (std::max(d, 0.0f) - std::max(d0, 0.0f));
    out.dp[i] = (d >= 0.0f) & (d0 >= 0.0f) ? both : general;
    out.rho[i] = rho;
    out.u_x[i] = ux;
    out.u_y[i] = uy;
    out.u_z[i] = uz;
  }
}

struct SurfaceHydrodynamics::Accumulator {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  Eigen::Vector3d tau = Eigen::Vector3d::Zero();
  double area = 0.0;
};

SurfaceHydrodynamics::SurfaceHydrodynamics(const geometry::TriangleMesh& mesh,
                                           HydrodynamicCoefficients coefficients,
                                           const std::vector<bool>& exposed)
    : coefficients_(coefficients) {
  if (mesh.positions.size() % 3 != 0 || mesh.indices.size() % 3 != 0) {
    throw std::invalid_argument("SurfaceHydrodynamics: positions/indices are not whole triples");
  }
  if (!exposed.empty() && exposed.size() != mesh.num_triangles()) {
    throw std::invalid_argument("SurfaceHydrodynamics: exposed flags must be empty or one per triangle");
  }
  const std::size_t nv = mesh.num_vertices();
  const std::size_t nt = mesh.num_triangles();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  auto vertex = [&](std::uint32_t k) {
    if (k >= nv) throw std::invalid_argument("SurfaceHydrodynamics: vertex index out of range");
    return Eigen::Vector3d(mesh.positions[3 * k], mesh.positions[3 * k + 1],
                           mesh.positions[3 * k + 2]);
  };
  for (std::size_t t = 0; t < nt; ++t) {
    const Eigen::Vector3d a = vertex(mesh.indices[3 * t]), b = vertex(mesh.indices[3 * t + 1]),
                          c = vertex(mesh.indices[3 * t + 2]);
    const Eigen::Vector3d cr = (b - a).cross(c - a);
    const double twice_area = cr.norm();
    if (!(twice_area > 0.0)) continue;
    push_face(faces_, 0.5 * twice_area, cr / twice_area, (a + b + c) / 3.0,
              geometry::triangle_second_moment(a, b, c), exposed.empty() || exposed[t] ? 1.0f : 0.0f);
    surface_area_ += 0.5 * twice_area;
    for (int k = 0; k < 3; ++k) {
      v_[k].push_back(static_cast<float>(a[k]));
      v_[3 + k].push_back(static_cast<float>(b[k]));
      v_[6 + k].push_back(static_cast<float>(c[k]));
    }
    lo = lo.cwiseMin(a).cwiseMin(b).cwiseMin(c);
    hi = hi.cwiseMax(a).cwiseMax(b).cwiseMax(c);
  }
  num_faces_ = faces_.size();
  pad(faces_);
  for (auto& v : v_) v.resize(faces_.size(), 0.0f);
  if (num_faces_ > 0) {
    sphere_center_B_ = 0.5 * (lo + hi);
    sphere_radius_ = 0.5 * (hi - lo).norm();
  }
  wet_mask_.assign(faces_.size(), 0.0f);
  ones_.assign(faces_.size(), 1.0f);  // clipped faces never outnumber the faces
  crossing_flags_.assign(faces_.size(), 0.0f);
}

void SurfaceHydrodynamics::accumulate(const HydroFaces& f, std::size_t begin, std::size_t end,
                                      const float* mask, const BodyMotion& m,
                                      const FluidSampler& fluid, double p_ref, Accumulator& acc) {
  const Eigen::Matrix3d R = m.X_WB.linear();
  const Eigen::Vector3d t = m.X_WB.translation() - m.p_WBcm;
  KernelParams k{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) k.R[3 * r + c] = static_cast<float>(R(r, c));
    k.t[r] = static_cast<float>(t[r]);
    k.v[r] = static_cast<float>(m.v_WBcm[r]);
    k.w[r] = static_cast<float>(m.w_WB[r]);
  }
  k.drag = static_cast<float>(0.5 * coefficients_.drag);
  k.friction = static_cast<float>(0.5 * coefficients_.skin_friction);
  k.lift = static_cast<float>(0.5 * coefficients_.lift);
  k.magnus = static_cast<float>(coefficients_.magnus);
  k.buoyancy = coefficients_.buoyancy ? 1.0f : 0.0f;
  k.p_ref = static_cast<float>(p_ref);
  k.g = coefficients_.buoyancy ? static_cast<float>(fluid.gravity_magnitude()) : 0.0f;
  // The pressure's gradient across a face, per rho g: -z_W, and with waves -(z_W - grad p_d / (rho g)) (the dynamic
  // pressure's gradient at the centre of mass), for the centre-of-pressure moments.
  const FluidSampler::WavesNear waves = fluid.waves_near(m.p_WBcm);
  const Eigen::Vector3d up_W =
      waves.density > 0.0 && coefficients_.buoyancy
          ? Eigen::Vector3d(Eigen::Vector3d::UnitZ() -
                            waves.pressure_gradient_W / (waves.density * fluid.gravity_magnitude()))
          : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up_B = R.transpose() * up_W;
  for (int c = 0; c < 3; ++c) k.up_B[c] = static_cast<float>(up_B[c]);

  alignas(64) float rx[kBlock], ry[kBlock], rz[kBlock];
  alignas(64) float rho[kBlock], dp[kBlock], ux[kBlock], uy[kBlock], uz[kBlock];
  const FluidSamples out{rho, dp, ux, uy, uz};
  for (std::size_t b = begin; b < end; b += kBlock) {
    const std::size_t n = std::min(kBlock, end - b);
    transform_centroids(&f.c_x[b], &f.c_y[b], &f.c_z[b], n, k, rx, ry, rz);
    fluid.sample(m.p_WBcm, n, rx, ry, rz, out);
    LaneSums s{};
    face_forces(&f.area[b], &f.n_x[b], &f.n_y[b], &f.n_z[b], mask + b, &f.exposed[b], rx, ry, rz,
                rho, dp, ux, uy, uz, &f.s_xx[b], &f.s_yy[b], &f.s_zz[b], &f.s_xy[b], &f.s_xz[b],
                &f.s_yz[b], n, k, s);
    for (std::size_t j = 0; j < kLanes; ++j) {
      acc.f += Eigen::Vector3d(s.f[0][j], s.f[1][j], s.f[2][j]);
      acc.tau += Eigen::Vector3d(s.f[3][j], s.f[4][j], s.f[5][j]);
      acc.area += s.area[j];
    }
  }
}

// Submerged part of each crossing face: the triangle clipped against h <= 0 (Sutherland-Hodgman
// against one plane gives a triangle or a quadrilateral), its area and area centroid by a fan of
// triangles, in B, and its second area moment. The normal is the face's.
void SurfaceHydrodynamics::clip_crossing_faces(const Eigen::Vector3d& g, double h0) {
  clear(clipped_);
  for (std::size_t i : crossing_) {
    std::array<Eigen::Vector3d, 3> tri;
    std::array<double, 3> h;
    for (int k = 0; k < 3; ++k) {
      tri[k] = Eigen::Vector3d(v_[3 * k][i], v_[3 * k + 1][i], v_[3 * k + 2][i]);
      h[k] = h0 + g.dot(tri[k]);
    }
    std::array<Eigen::Vector3d, 4> poly;
    int count = 0;
    for (int k = 0; k < 3; ++k) {
      const int l = (k + 1) % 3;
      if (h[k] <= 0.0) poly[count++] = tri[k];
      if ((h[k] < 0.0 && h[l] > 0.0) || (h[k] > 0.0 && h[l] < 0.0)) {
        const double s = h[k] / (h[k] - h[l]);
        poly[count++] = tri[k] + s * (tri[l] - tri[k]);
      }
    }
    double area = 0.0;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    std::array<double, 2> sub_area{};
    std::array<Eigen::Vector3d, 2> sub_centroid;
    for (int k = 1; k + 1 < count; ++k) {
      const double a = 0.5 * (poly[k] - poly[0]).cross(poly[k + 1] - poly[0]).norm();
      sub_area[k - 1] = a;
      sub_centroid[k - 1] = (poly[0] + poly[k] + poly[k + 1]) / 3.0;
      area += a;
      centroid += a * sub_centroid[k - 1];
    }
    if (!(area > 0.0)) continue;
    centroid /= area;
    // Second moment about the polygon's centroid: each fan triangle's own plus its parallel-axis
    // shift.
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    for (int k = 1; k + 1 < count; ++k) {
      const Eigen::Vector3d d = sub_centroid[k - 1] - centroid;
      C += sub_area[k - 1] * (geometry::triangle_second_moment(poly[0], poly[k], poly[k + 1]) + d * d.transpose());
    }
    push_face(clipped_, area, Eigen::Vector3d(faces_.n_x[i], faces_.n_y[i], faces_.n_z[i]),
              centroid, C / area, faces_.exposed[i]);
  }
  pad(clipped_);
}

HydrodynamicWrench SurfaceHydrodynamics::compute(const BodyMotion& m, const FluidSampler& fluid) {
  HydrodynamicWrench w;
  if (num_faces_ == 0) return w;
  // The surface near the body as a plane h(x_W) = q . x_W - c0 (height above it), q = (-s_x, -s_y, 1): flat without
  // waves. Over the bounding sphere the plane lies within `reach` of its height at the sphere's centre.
  const Eigen::Vector3d center_W = m.X_WB * sphere_center_B_;
  const FluidSampler::SurfacePlane plane = fluid.surface_plane(center_W);
  const Eigen::Vector3d q(-plane.slope_x, -plane.slope_y, 1.0);
  const double c0 = plane.height - plane.slope_x * center_W.x() - plane.slope_y * center_W.y();
  const double reach = sphere_radius_ * std::hypot(plane.slope_x, plane.slope_y);
  Accumulator acc;
  if (center_W.z() + sphere_radius_ <= plane.height - reach) {
    // Fully submerged (bounding sphere under water): no classification, constant pressure dropped.
    accumulate(faces_, 0, faces_.size(), ones_.data(), m, fluid, 0.0, acc);
    w.fully_submerged = true;
  } else if (center_W.z() - sphere_radius_ >= plane.height + reach) {
    return w;  // in the air
  } else {
    // h(x_B) = h0 + g . x_B in B.
    const Eigen::Vector3d g = m.X_WB.linear().transpose() * q;
    const double h0 = q.dot(m.X_WB.translation()) - c0;
    const float* v[9];
    for (int k = 0; k < 9; ++k) v[k] = v_[k].data();
    classify(v, faces_.size(), static_cast<float>(h0), static_cast<float>(g.x()), static_cast<float>(g.y()),
             static_cast<float>(g.z()), wet_mask_.data(), crossing_flags_.data());
    crossing_.clear();
    for (std::size_t i = 0; i < num_faces_; ++i) {
      if (crossing_flags_[i] != 0.0f) crossing_.push_back(i);
    }
    for (std::size_t i = num_faces_; i < faces_.size(); ++i) wet_mask_[i] = 0.0f;
    const double p_ref = fluid.gauge_pressure_at(m.p_WBcm);
    accumulate(faces_, 0, faces_.size(), wet_mask_.data(), m, fluid, p_ref, acc);
    clip_crossing_faces(g, h0);
    if (clipped_.size() > 0) {
      accumulate(clipped_, 0, clipped_.size(), ones_.data(), m, fluid, p_ref, acc);
    }
    w.clipped_faces = crossing_.size();
  }
  w.f_W = acc.f;
  w.tau_W = acc.tau;
  w.wetted_area = acc.area;
  return w;
}

}  // namespace hadal::physics

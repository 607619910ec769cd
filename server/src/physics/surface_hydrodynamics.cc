#include "hadal/physics/surface_hydrodynamics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>

#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/triangle_mesh.h"

#include "face_kernel.h"
#include "hadal/core/vector_kernel.h"

namespace hadal::physics {

namespace face_kernel {
namespace vector {
#define HADAL_FACE_KERNEL HADAL_VECTOR_KERNEL
#include "face_kernel.inc"
#undef HADAL_FACE_KERNEL
}  // namespace vector

const Kernel& vector_kernel() { return vector::kernel_table(); }
}  // namespace face_kernel

namespace {

constexpr std::size_t kLanes = SurfaceHydrodynamics::kLanes;
constexpr std::size_t kBlock = SurfaceHydrodynamics::kBlock;

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

void SurfaceHydrodynamics::use_scalar_kernel(bool on) { kernel_ = on ? &face_kernel::scalar_kernel() : nullptr; }

const face_kernel::Kernel& SurfaceHydrodynamics::kernel() const {
  return kernel_ != nullptr ? *kernel_ : face_kernel::vector_kernel();
}

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
                                      const FluidSampler& fluid, double p_ref,
                                      const FluidSampler::Uniform* uniform, Accumulator& acc) {
  const face_kernel::Kernel& loops = kernel();
  const Eigen::Matrix3d R = m.X_WB.linear();
  const Eigen::Vector3d t = m.X_WB.translation() - m.p_WBcm;
  face_kernel::Params k{};
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
  if (uniform != nullptr) {
    k.rho = static_cast<float>(uniform->density);
    k.rho_g = static_cast<float>(uniform->density * fluid.gravity_magnitude());
    for (int c = 0; c < 3; ++c) k.u[c] = static_cast<float>(uniform->current_W[c]);
  }
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
  Eigen::Vector3d tau_B = Eigen::Vector3d::Zero();  // centre-of-pressure moments, in B
  for (std::size_t b = begin; b < end; b += kBlock) {
    const std::size_t n = std::min(kBlock, end - b);
    const face_kernel::FaceBlock block{&f.area[b], &f.n_x[b],  &f.n_y[b],  &f.n_z[b],  &f.c_x[b],
                                       &f.c_y[b],  &f.c_z[b],  &f.s_xx[b], &f.s_yy[b], &f.s_zz[b],
                                       &f.s_xy[b], &f.s_xz[b], &f.s_yz[b], &f.exposed[b]};
    face_kernel::LaneSums s{};
    if (uniform != nullptr) {
      loops.face_forces_uniform(block, n, k, s);
    } else {
      loops.transform_centroids(block, n, k, rx, ry, rz);
      fluid.sample(m.p_WBcm, n, rx, ry, rz, out);
      loops.face_forces(block, mask + b, rx, ry, rz, out, n, k, s);
    }
    for (std::size_t j = 0; j < kLanes; ++j) {
      acc.f += Eigen::Vector3d(s.f[0][j], s.f[1][j], s.f[2][j]);
      acc.tau += Eigen::Vector3d(s.f[3][j], s.f[4][j], s.f[5][j]);
      tau_B += Eigen::Vector3d(s.f[6][j], s.f[7][j], s.f[8][j]);
      acc.area += s.area[j];
    }
  }
  acc.tau += R * tau_B;
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
    // Uniform water: density, current and the pressure's gradient are the kernel's constants.
    const std::optional<FluidSampler::Uniform> uniform = fluid.uniform();
    accumulate(faces_, 0, faces_.size(), ones_.data(), m, fluid, 0.0, uniform ? &*uniform : nullptr, acc);
    w.fully_submerged = true;
  } else if (center_W.z() - sphere_radius_ >= plane.height + reach) {
    return w;  // in the air
  } else {
    // h(x_B) = h0 + g . x_B in B.
    const Eigen::Vector3d g = m.X_WB.linear().transpose() * q;
    const double h0 = q.dot(m.X_WB.translation()) - c0;
    const float* v[9];
    for (int k = 0; k < 9; ++k) v[k] = v_[k].data();
    const face_kernel::Kernel& loops = kernel();
    loops.classify(v, faces_.size(), static_cast<float>(h0), static_cast<float>(g.x()), static_cast<float>(g.y()),
             static_cast<float>(g.z()), wet_mask_.data(), crossing_flags_.data());
    crossing_.clear();
    for (std::size_t i = 0; i < num_faces_; ++i) {
      if (crossing_flags_[i] != 0.0f) crossing_.push_back(i);
    }
    for (std::size_t i = num_faces_; i < faces_.size(); ++i) wet_mask_[i] = 0.0f;
    const double p_ref = fluid.gauge_pressure_at(m.p_WBcm);
    accumulate(faces_, 0, faces_.size(), wet_mask_.data(), m, fluid, p_ref, nullptr, acc);
    clip_crossing_faces(g, h0);
    if (clipped_.size() > 0) {
      accumulate(clipped_, 0, clipped_.size(), ones_.data(), m, fluid, p_ref, nullptr, acc);
    }
    w.clipped_faces = crossing_.size();
  }
  w.f_W = acc.f;
  w.tau_W = acc.tau;
  w.wetted_area = acc.area;
  return w;
}

}  // namespace hadal::physics

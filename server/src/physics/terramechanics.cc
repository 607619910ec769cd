#include "hadal/physics/terramechanics.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/seabed_height.h"
#include "hadal/geometry/triangle_mesh.h"

namespace hadal::physics {

namespace {

// Faces are split until no edge is longer than this [m] (header: pressure is sampled per face).
constexpr double kMaxFaceSize = 0.1;

// The soil has yielded once 1 - e^(-j/K) reaches 0.999: j_cap = K ln(1000) (header).
const double kShearCapPerK = std::log(1000.0);

void check_parameters(const SoilParameters& s) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("SoilParameters: " + what); };
  if (!(s.sinkage_exponent > 0.0) || !std::isfinite(s.sinkage_exponent)) fail("sinkage_exponent must be > 0");
  if (!(s.k_c >= 0.0) || !std::isfinite(s.k_c)) fail("k_c must be >= 0");
  if (!(s.k_phi >= 0.0) || !std::isfinite(s.k_phi)) fail("k_phi must be >= 0");
  if (!(s.cohesion >= 0.0) || !std::isfinite(s.cohesion)) fail("cohesion must be >= 0");
  if (!(s.friction_angle >= 0.0) || !(s.friction_angle < 0.5 * M_PI)) fail("friction_angle must be in [0, pi/2)");
  if (!(s.shear_deformation_modulus > 0.0) || !std::isfinite(s.shear_deformation_modulus)) {
    fail("shear_deformation_modulus must be > 0");
  }
  if (!(s.damping >= 0.0) || !std::isfinite(s.damping)) fail("damping must be >= 0");
  if (!(s.shear_damping_time >= 0.0) || !std::isfinite(s.shear_damping_time)) fail("shear_damping_time must be >= 0");
}

}  // namespace

double SoilParameters::pressure(double sinkage, double width) const {
  if (!(sinkage > 0.0)) return 0.0;
  return (k_c / width + k_phi) * std::pow(sinkage, sinkage_exponent);
}

double SoilParameters::shear_strength(double p) const { return cohesion + p * std::tan(friction_angle); }

double SoilParameters::static_sinkage(double load, double area, double width) const {
  return std::pow(load / (area * (k_c / width + k_phi)), 1.0 / sinkage_exponent);
}

std::size_t SoilRegionMap::region_at(double x_W, double y_W) const {
  const double column = std::floor((x_W - center_W.x()) / meters_per_pixel + 0.5 * columns);
  const double row = std::floor((center_W.y() - y_W) / meters_per_pixel + 0.5 * rows);
  if (!(column >= 0.0 && column < columns && row >= 0.0 && row < rows)) return 0;
  return index[static_cast<std::size_t>(row) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(column)];
}

SoilContact::SoilContact(const geometry::TriangleMesh& mesh, const SoilParameters& soil, double mass, double dt)
    : SoilContact(mesh, SoilLayout{{soil}, nullptr}, mass, dt) {}

SoilContact::SoilContact(const geometry::TriangleMesh& mesh, SoilLayout layout, double mass, double dt)
    : layout_(std::move(layout)), mass_(mass), dt_(dt) {
  if (layout_.soils.empty()) throw std::invalid_argument("SoilContact: no soil");
  for (const SoilParameters& soil : layout_.soils) {
    check_parameters(soil);
    tan_phi_.push_back(std::tan(soil.friction_angle));
  }
  if (layout_.map) {
    const SoilRegionMap& map = *layout_.map;
    if (!(map.meters_per_pixel > 0.0) || map.columns < 1 || map.rows < 1 ||
        map.index.size() != static_cast<std::size_t>(map.columns) * static_cast<std::size_t>(map.rows)) {
      throw std::invalid_argument("SoilContact: malformed soil map");
    }
    for (const std::uint8_t region : map.index) {
      if (region >= layout_.soils.size()) throw std::invalid_argument("SoilContact: soil map names a missing region");
    }
  }
  if (!(mass > 0.0) || !(dt > 0.0)) throw std::invalid_argument("SoilContact: mass and dt must be > 0");
  if (mesh.positions.size() % 3 != 0 || mesh.indices.size() % 3 != 0) {
    throw std::invalid_argument("SoilContact: positions/indices are not whole triples");
  }
  const std::size_t nv = mesh.num_vertices();
  const bool has_materials = mesh.triangle_materials.size() == mesh.num_triangles();
  std::vector<std::vector<Face>> by_link;
  for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
    Eigen::Vector3d v[3];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t index = mesh.indices[3 * t + k];
      if (index >= nv) throw std::invalid_argument("SoilContact: vertex index out of range");
      v[k] = Eigen::Vector3d(mesh.positions[3 * index], mesh.positions[3 * index + 1], mesh.positions[3 * index + 2]);
    }
    const Eigen::Vector3d cross = (v[1] - v[0]).cross(v[2] - v[0]);
    const double twice_area = cross.norm();
    if (!(twice_area > 0.0)) continue;
    const Eigen::Vector3d normal = cross / twice_area;
    const std::size_t link = has_materials ? geometry::link_of_material(mesh.triangle_materials[t]) : 0;
    if (link >= by_link.size()) by_link.resize(link + 1);
    // Split at the midpoint of the longest edge until no edge is longer than kMaxFaceSize: pieces of
    // kMaxFaceSize / 2 .. kMaxFaceSize across in every direction, whatever the triangle's shape.
    std::vector<std::array<Eigen::Vector3d, 3>> pending = {{v[0], v[1], v[2]}};
    while (!pending.empty()) {
      const std::array<Eigen::Vector3d, 3> tri = pending.back();
      pending.pop_back();
      int longest = 0;
      double length = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double edge = (tri[(k + 1) % 3] - tri[k]).norm();
        if (edge > length) {
          length = edge;
          longest = k;
        }
      }
      if (length > kMaxFaceSize) {
        const Eigen::Vector3d& a = tri[longest];
        const Eigen::Vector3d& b = tri[(longest + 1) % 3];
        const Eigen::Vector3d& c = tri[(longest + 2) % 3];
        const Eigen::Vector3d m = 0.5 * (a + b);
        pending.push_back({a, m, c});
        pending.push_back({m, b, c});
        continue;
      }
      const double area = 0.5 * (tri[1] - tri[0]).cross(tri[2] - tri[0]).norm();
      if (!(area > 0.0)) continue;
      by_link[link].push_back(Face{area, normal, (tri[0] + tri[1] + tri[2]) / 3.0,
                                   geometry::triangle_second_moment(tri[0], tri[1], tri[2]), link});
    }
  }
  num_links_ = by_link.size();
  // Faces in link order, each link's range with its bounding sphere (culled as a whole).
  for (std::size_t link = 0; link < num_links_; ++link) {
    LinkFaces range;
    range.begin = faces_.size();
    Eigen::AlignedBox3d bounds;
    for (const Face& face : by_link[link]) {
      faces_.push_back(face);
      bounds.extend(face.c_B);  // contact is decided at centroids, so their sphere is enough
    }
    range.end = faces_.size();
    if (range.end > range.begin) {
      range.center_B = bounds.center();
      range.radius = 0.5 * bounds.diagonal().norm();
    }
    links_.push_back(range);
  }
  c_x_.resize(faces_.size());
  c_y_.resize(faces_.size());
  c_z_.resize(faces_.size());
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    c_x_[f] = faces_[f].c_B.x();
    c_y_[f] = faces_[f].c_B.y();
    c_z_[f] = faces_[f].c_B.z();
  }
  patch_width_.assign(num_links_, 0.0);
  contacts_.reserve(faces_.size());
}

SoilWrench SoilContact::compute(const BodyMotion& motion, const geometry::SeabedHeight& seabed,
                                SoilShearState& shear, const std::vector<Eigen::Vector3d>& belt_velocity_B) {
  SoilWrench out;
  out.link_shear_force_W.assign(num_links_, Eigen::Vector3d::Zero());
  if (shear.size() != faces_.size()) {
    shear.assign(faces_.size(), Eigen::Vector3d::Zero());
    shear_clear_ = true;
  }
  std::fill(patch_width_.begin(), patch_width_.end(), 0.0);
  contacts_.clear();
  const Eigen::Matrix3d R = motion.X_WB.linear();
  // Cull link by link: a link whose bounding sphere is above the highest seabed under it touches nothing;
  // of the others, only faces whose centroid is below that height are sampled.
  geometry::SeabedHeight::Sample ground;
  std::uint32_t hint = geometry::SeabedHeight::kNoHint;
  const double r20 = R(2, 0), r21 = R(2, 1), r22 = R(2, 2), t_z = motion.X_WB.translation().z();
  for (const LinkFaces& link : links_) {
    if (link.end == link.begin) continue;
    const Eigen::Vector3d center_W = motion.X_WB * link.center_B;
    const Eigen::AlignedBox2d under(center_W.head<2>() - Eigen::Vector2d::Constant(link.radius),
                                    center_W.head<2>() + Eigen::Vector2d::Constant(link.radius));
    const double top = seabed.max_height_in(under);
    if (!(center_W.z() - link.radius < top)) continue;
    for (std::size_t f = link.begin; f < link.end; ++f) {
      if (r20 * c_x_[f] + r21 * c_y_[f] + r22 * c_z_[f] + t_z >= top) continue;
      const Face& face = faces_[f];
      const Eigen::Vector3d c_W = motion.X_WB * face.c_B;
      if (!seabed.sample(c_W.x(), c_W.y(), &ground, &hint)) continue;
      const double sinkage = ground.normal_W.z() * (ground.height - c_W.z());
      const double facing = -(R * face.n_B).dot(ground.normal_W);
      if (!(sinkage > 0.0) || !(facing > 0.0)) continue;
      contacts_.push_back(
          Contact{f, layout_.region_at(c_W.x(), c_W.y()), sinkage, face.area * facing, c_W, ground.normal_W});
    }
  }
  // Faces that left contact lose their shear.
  std::size_t next = 0;
  if (!shear_clear_) {
    for (const Contact& contact : contacts_) {
      for (; next < contact.face; ++next) shear[next].setZero();
      next = contact.face + 1;
    }
    for (; next < faces_.size(); ++next) shear[next].setZero();
  }
  shear_clear_ = contacts_.empty();
  if (contacts_.empty()) return out;

  std::vector<Patch>& patches = patches_;
  patches.assign(num_links_, Patch{});
  for (const Contact& contact : contacts_) {
    Patch& patch = patches[faces_[contact.face].link];
    patch.area += contact.bearing_area;
    patch.first += contact.bearing_area * contact.c_W;
    patch.second += contact.bearing_area * contact.c_W * contact.c_W.transpose();
    patch.own += contact.bearing_area * faces_[contact.face].C_B;
    patch.normal += contact.bearing_area * contact.n_s;
  }
  for (std::size_t link = 0; link < num_links_; ++link) {
    Patch& patch = patches[link];
    if (!(patch.area > 0.0)) continue;
    const Eigen::Vector3d n = patch.normal.normalized();
    const Eigen::Vector3d mean = patch.first / patch.area;
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n * n.transpose();
    const Eigen::Matrix3d spread = (patch.second + R * patch.own * R.transpose()) / patch.area - mean * mean.transpose();
    const Eigen::Matrix3d C = P * spread * P;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(C, Eigen::EigenvaluesOnly);
    // Eigenvalues ascending: ~0 along n, then the patch's short and long in-plane directions.
    patch_width_[link] = std::sqrt(12.0 * std::max(solver.eigenvalues()(1), 0.0));
    if (link < belt_velocity_B.size()) {
      const Eigen::Vector3d v = P * (R * belt_velocity_B[link]);
      patch.belt_W = R * belt_velocity_B[link];
      patch.belt_speed = v.norm();
      if (patch.belt_speed > 0.0) patch.belt_direction = v / patch.belt_speed;
    }
  }
  for (const Contact& contact : contacts_) {
    Patch& patch = patches[faces_[contact.face].link];
    if (!(patch.belt_speed > 0.0)) continue;
    const Eigen::Vector3d& u = patch.belt_direction;
    const Eigen::Vector3d u_B = R.transpose() * u;
    const double half_length = std::sqrt(3.0 * std::max(u_B.dot(faces_[contact.face].C_B * u_B), 0.0));
    patch.leading_edge = std::min(patch.leading_edge, u.dot(contact.c_W) - half_length);
  }

  // Forces, each face with the soil under it. The damping coefficients summed over the faces are capped
  // at mass / dt (header).
  double normal_damping_sum = 0.0;
  for (const Contact& contact : contacts_) {
    normal_damping_sum += layout_.soils[contact.region].damping * contact.bearing_area;
  }
  const double normal_damping_scale =
      normal_damping_sum * dt_ > mass_ ? mass_ / (normal_damping_sum * dt_) : 1.0;
  std::vector<FaceForce>& face_forces = face_forces_;
  face_forces.clear();
  double shear_damping_sum = 0.0;
  for (const Contact& contact : contacts_) {
    const SoilParameters& s = layout_.soils[contact.region];
    const double K = s.shear_deformation_modulus;
    const double j_cap = kShearCapPerK * K;
    const Face& face = faces_[contact.face];
    const Patch& patch = patches[face.link];
    const double width = patch_width_[face.link];
    const double p = width > 0.0 ? s.pressure(contact.sinkage, width) : 0.0;
    const double A = contact.bearing_area;
    const Eigen::Vector3d& n_s = contact.n_s;
    const Eigen::Vector3d r = contact.c_W - motion.p_WBcm;
    const Eigen::Vector3d v = motion.v_WBcm + motion.w_WB.cross(r) + patch.belt_W;  // over the soil
    const double v_n = v.dot(n_s);
    const Eigen::Vector3d v_t = v - v_n * n_s;
    // Shear displacement: onto the current seabed plane, plus this step's slip; a belt element's
    // relaxes by the time it has been in contact (header), implicitly.
    Eigen::Vector3d& j = shear[contact.face];
    j -= j.dot(n_s) * n_s;
    j += v_t * dt_;
    if (patch.belt_speed > 0.0) {
      const double s_travel = std::max(patch.belt_direction.dot(contact.c_W) - patch.leading_edge, 1e-9);
      j /= 1.0 + dt_ * patch.belt_speed / s_travel;
    }
    const double j_norm = j.norm();
    if (j_norm > j_cap) {
      j *= j_cap / j_norm;
    }
    const double j_len = std::min(j_norm, j_cap);
    const double tau_max = s.cohesion + p * tan_phi_[contact.region];
    const double e = std::exp(-j_len / K);
    // Normal: pressure less damping (scaled), never pulling; added here with its moment. The shear is
    // kept apart to be clipped with its damping below.
    const double normal_stress = std::max(0.0, p - normal_damping_scale * s.damping * v_n);
    const Eigen::Vector3d f_n = normal_stress * A * n_s;
    out.normal_force_W += f_n;
    out.f_W += f_n;
    out.tau_W += r.cross(f_n);
    FaceForce force;
    force.r = r;
    force.limit = A * tau_max;
    force.elastic = j_len > 0.0 ? Eigen::Vector3d(-(A * tau_max * (1.0 - e) / j_len) * j) : Eigen::Vector3d::Zero();
    const double shear_damping = s.shear_damping_time * A * tau_max * e / K;
    shear_damping_sum += shear_damping;
    force.damping = -shear_damping * v_t;
    force.link = face.link;
    face_forces.push_back(force);
    out.contact_area += A;
    out.max_sinkage = std::max(out.max_sinkage, contact.sinkage);
  }
  const double shear_damping_scale = shear_damping_sum * dt_ > mass_ ? mass_ / (shear_damping_sum * dt_) : 1.0;
  for (const FaceForce& force : face_forces) {
    Eigen::Vector3d f_t = force.elastic + shear_damping_scale * force.damping;
    const double magnitude = f_t.norm();
    if (magnitude > force.limit) f_t *= force.limit / magnitude;
    out.shear_force_W += f_t;
    out.link_shear_force_W[force.link] += f_t;
    out.f_W += f_t;
    out.tau_W += force.r.cross(f_t);
  }
  out.faces_in_contact = contacts_.size();
  return out;
}

SoilForces::SoilForces(const geometry::TriangleMesh& mesh_B, SoilLayout layout, const geometry::SeabedHeight& seabed,
                       double mass, double dt)
    : contact_(mesh_B, std::move(layout), mass, dt), seabed_(seabed) {}

void SoilForces::add(const ForceInput& in, StepWrench& out) {
  if (!in.soil_shear) throw std::logic_error("SoilForces: the vehicle has no soil shear state");
  BodyMotion motion;
  motion.X_WB = in.body.X_WB;
  motion.p_WBcm = in.p_WBcm;
  motion.v_WBcm = in.v_WBcm;
  motion.w_WB = in.body.w_WB;
  static const std::vector<Eigen::Vector3d> kNoBelts;
  last_ = contact_.compute(motion, seabed_, *in.soil_shear, in.belt_velocity_B ? *in.belt_velocity_B : kNoBelts);
  out.f_W += last_.f_W;
  out.tau_W += last_.tau_W;
}

}  // namespace hadal::physics

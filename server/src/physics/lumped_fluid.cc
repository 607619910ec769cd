#include "hadal/physics/lumped_fluid.h"
#include "hadal/core/units.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hadal::physics {

namespace {
}  // namespace

LumpedFluid::LumpedFluid(const VehicleSpec& vehicle, const WorldSpec& world)
    : surface_z_(world.water.surface_z),
      density_(world.water.density),
      gravity_W_(world.gravity_W),
      linear_damping_(vehicle.fluid.linear_damping),
      quadratic_damping_(vehicle.fluid.quadratic_damping) {
  for (const LinkSpec& link : vehicle.links) {
    LinkVolume lv;
    lv.volume = link.buoyancy.volume;
    lv.p_BCb = link.X_BL * link.buoyancy.p_LCb;
    lv.first_shape = static_cast<int>(shapes_.size());
    lv.num_shapes = static_cast<int>(link.collisions.size());
    lv.height_without_shapes = 2.0 * std::cbrt(3.0 * std::max(lv.volume, 0.0) / (4.0 * kPi));
    for (const CollisionShape& shape : link.collisions) {
      const Eigen::Isometry3d X_BG = link.X_BL * shape.X_LG;
      shapes_.push_back(ShapeExtent{shape.type, X_BG.linear(), X_BG.translation(),
                                    0.5 * shape.box_size, shape.radius, 0.5 * shape.length});
    }
    total_volume_ += lv.volume;
    links_.push_back(lv);
  }
}

double LumpedFluid::vertical_half_extent(const ShapeExtent& shape, const Eigen::Matrix3d& R_WB) {
  // Row z of R_WG: the W-z components of G's axes.
  const Eigen::RowVector3d z_G = R_WB.row(2) * shape.R_BG;
  switch (shape.type) {
    case CollisionShapeType::kBox:
      return z_G.cwiseAbs().dot(shape.half_size.transpose());
    case CollisionShapeType::kSphere:
      return shape.radius;
    case CollisionShapeType::kCylinder: {
      const double a = std::min(std::abs(z_G.z()), 1.0);  // |cos| of the axis tilt from W-z
      return a * shape.half_length + shape.radius * std::sqrt(1.0 - a * a);
    }
    case CollisionShapeType::kCapsule:
      return std::abs(z_G.z()) * shape.half_length + shape.radius;
  }
  return 0.0;
}

double LumpedFluid::link_submerged_fraction(int link, const Eigen::Isometry3d& X_WB) const {
  const LinkVolume& lv = links_[link];
  const Eigen::Matrix3d& R_WB = X_WB.linear();
  const double z_WB = X_WB.translation().z();
  const double z_Cb = z_WB + R_WB.row(2).dot(lv.p_BCb);
  double height = lv.height_without_shapes;
  if (lv.num_shapes > 0) {
    double z_low = std::numeric_limits<double>::infinity();
    double z_high = -std::numeric_limits<double>::infinity();
    for (int s = lv.first_shape; s < lv.first_shape + lv.num_shapes; ++s) {
      const ShapeExtent& shape = shapes_[s];
      const double z_G = z_WB + R_WB.row(2).dot(shape.p_BG);
      const double half = vertical_half_extent(shape, R_WB);
      z_low = std::min(z_low, z_G - half);
      z_high = std::max(z_high, z_G + half);
    }
    height = z_high - z_low;
  }
  if (!(height > 0.0)) return z_Cb <= surface_z_ ? 1.0 : 0.0;
  return std::clamp((surface_z_ - (z_Cb - 0.5 * height)) / height, 0.0, 1.0);
}

LumpedFluidWrench LumpedFluid::wrench(const RigidBodyState& body,
                                      const Eigen::Vector3d& v_water_W) const {
  LumpedFluidWrench out;
  const Eigen::Matrix3d& R_WB = body.X_WB.linear();
  const Eigen::Vector3d p_WB = body.X_WB.translation();

  double submerged_volume = 0.0;
  for (int i = 0; i < static_cast<int>(links_.size()); ++i) {
    const LinkVolume& lv = links_[i];
    if (lv.volume <= 0.0) continue;
    const double s = link_submerged_fraction(i, body.X_WB);
    if (s <= 0.0) continue;
    submerged_volume += s * lv.volume;
    const Eigen::Vector3d f_W = -s * density_ * lv.volume * gravity_W_;
    const Eigen::Vector3d p_BoCb_W = R_WB * lv.p_BCb;
    out.f_buoyancy_W += f_W;
    out.tau_buoyancy_W += p_BoCb_W.cross(f_W);
  }
  if (total_volume_ > 0.0) {
    out.submerged_fraction = submerged_volume / total_volume_;
  } else {
    out.submerged_fraction = p_WB.z() <= surface_z_ ? 1.0 : 0.0;
  }

  if (out.submerged_fraction > 0.0) {
    Vector6d nu;
    nu.head<3>() = R_WB.transpose() * (body.v_WB - v_water_W);
    nu.tail<3>() = R_WB.transpose() * body.w_WB;
    const Vector6d tau_B =
        -out.submerged_fraction *
        (linear_damping_ + quadratic_damping_.cwiseProduct(nu.cwiseAbs())).cwiseProduct(nu);
    out.f_damping_W = R_WB * tau_B.head<3>();
    out.tau_damping_W = R_WB * tau_B.tail<3>();
  }
  return out;
}

}  // namespace hadal::physics

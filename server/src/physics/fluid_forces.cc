#include "hadal/physics/fluid_forces.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/shape_overlap.h"
#include "hadal/physics/added_mass.h"
#include "hadal/physics/lumped_fluid.h"
#include "hadal/physics/ocean.h"
#include "hadal/physics/ocean_fluid.h"
#include "hadal/physics/surface_hydrodynamics.h"

namespace hadal::physics {

namespace {

// The vehicle's hydrodynamic mesh in B (geometry::vehicle_surface_B).
geometry::TriangleMesh hydrodynamic_mesh_B(const VehicleSpec& spec) {
  geometry::TriangleMesh mesh_B = geometry::vehicle_surface_B(spec);
  if (mesh_B.num_triangles() == 0) {
    throw std::invalid_argument("vehicle '" + spec.name +
                                "': fluid model 'surface' needs a hydrodynamic mesh: no link has a "
                                "mesh or collision shapes");
  }
  return mesh_B;
}

// Parts of a hull built from primitives may overlap. Each tessellated part is closed and integrates
// its own pressure, so the overlap displaces water twice; and faces of one part that lie inside
// another meet no flow. The hull keeps every face for buoyancy, turns the flow terms off on faces
// whose centroid lies inside another primitive (exposed = false), and the doubly counted volume
// (geometry/shape_overlap.h: excess volume E and its centroid, from the smooth primitives; the
// inscribed tessellation overlaps slightly less, so E over-corrects by ~2 % of itself) is taken
// back each step as a downward force rho g E at its centroid.
struct HydrodynamicHull {
  geometry::TriangleMesh mesh_B;
  std::vector<bool> exposed;  // one per triangle
  double excess_volume = 0.0;                                 // E [m^3]
  Eigen::Vector3d p_BE = Eigen::Vector3d::Zero();             // its centroid in B
  Eigen::Matrix3d C_E = Eigen::Matrix3d::Zero();              // its second moment about p_BE [m^5]
};

HydrodynamicHull hydrodynamic_hull(const VehicleSpec& spec) {
  HydrodynamicHull hull;
  hull.mesh_B = hydrodynamic_mesh_B(spec);
  hull.exposed.assign(hull.mesh_B.num_triangles(), true);
  // The primitives that became faces, in B, with the index of their first triangle.
  std::vector<std::pair<CollisionShape, Eigen::Isometry3d>> shapes_B;
  std::vector<std::size_t> first_triangle;
  std::size_t triangle = 0;
  for (const LinkSpec& link : spec.links) {
    if (link.mesh && link.mesh->mesh) {
      triangle += link.mesh->mesh->num_triangles();
      continue;
    }
    for (const CollisionShape& shape : link.collisions) {
      shapes_B.emplace_back(shape, link.X_BL * shape.X_LG);
      first_triangle.push_back(triangle);
      triangle += geometry::tessellate(shape).num_triangles();
    }
  }
  first_triangle.push_back(triangle);
  if (shapes_B.size() < 2) return hull;
  double volume = 0.0;
  for (const auto& shape : shapes_B) {
    volume += std::abs(geometry::compute_mesh_properties(geometry::tessellate(shape.first)).volume);
  }
  geometry::OverlapExcessOptions options;
  options.absolute_tolerance = 1e-4 * volume;
  const geometry::OverlapExcess excess = geometry::overlap_excess(shapes_B, options);
  if (excess.overlapping_pairs.empty()) return hull;
  hull.excess_volume = excess.volume;
  hull.p_BE = excess.centroid_B;
  hull.C_E = excess.second_moment_B;
  const geometry::TriangleMesh& mesh = hull.mesh_B;
  for (std::size_t part = 0; part < shapes_B.size(); ++part) {
    for (std::size_t t = first_triangle[part]; t < first_triangle[part + 1]; ++t) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = mesh.indices[3 * t + k];
        c += Eigen::Vector3d(mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
      }
      c /= 3.0;
      for (std::size_t other = 0; other < shapes_B.size(); ++other) {
        if (other != part && geometry::contains(shapes_B[other].first, shapes_B[other].second, c)) {
          hull.exposed[t] = false;
          break;
        }
      }
    }
  }
  return hull;
}

// Volume properties of the hull's union: the parts' (each closed part integrated by the divergence
// theorem) less the doubly counted overlap E with centroid p_BE and second moment C_E about it.
geometry::MeshProperties union_properties(const HydrodynamicHull& hull) {
  geometry::MeshProperties props = geometry::compute_mesh_properties(hull.mesh_B);
  const double E = hull.excess_volume;
  if (!(E > 0.0) || !props.closed || !(props.volume > E)) return props;
  const auto second_moment = [](const Eigen::Matrix3d& I) {  // I = tr(C) 1 - C  =>  C = tr(I)/2 1 - I
    return Eigen::Matrix3d(0.5 * I.trace() * Eigen::Matrix3d::Identity() - I);
  };
  const double V = props.volume - E;
  const Eigen::Vector3d c = (props.volume * props.centroid - E * hull.p_BE) / V;
  const Eigen::Vector3d dp = props.centroid - c, de = hull.p_BE - c;
  const Eigen::Matrix3d C = second_moment(props.inertia_unit_density) +
                            props.volume * dp * dp.transpose() - hull.C_E -
                            E * de * de.transpose();
  props.volume = V;
  props.centroid = c;
  props.inertia_unit_density = C.trace() * Eigen::Matrix3d::Identity() - C;
  return props;
}

// M_A0 about the centre of mass p_BBcm in B axes (physics/added_mass.h, AddedMassSpec). `hull` is
// the vehicle's hydrodynamic hull (needed by an ellipsoid fitted to it).
Matrix6d surface_added_mass(const VehicleSpec& spec, const HydrodynamicHull* hull,
                            const Eigen::Vector3d& p_BBcm, double surface_density) {
  const AddedMassSpec& added = spec.fluid.added_mass;
  switch (added.model) {
    case AddedMassModel::kNone:
      return Matrix6d::Zero();
    case AddedMassModel::kMatrix:
      return shift_added_mass(added.M_A0, Eigen::Matrix3d::Identity(), added.p_BR, p_BBcm);
    case AddedMassModel::kEllipsoid:
      break;
  }
  Ellipsoid ellipsoid;
  if (added.semi_axes_E) {
    ellipsoid.semi_axes = *added.semi_axes_E;
    ellipsoid.X_BE = added.X_BE;
  } else {
    try {
      if (!hull) throw std::invalid_argument("no link has a mesh or collision shapes");
      ellipsoid = equivalent_ellipsoid(union_properties(*hull));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("vehicle '" + spec.name + "': fluid.added_mass: " + e.what() +
                                  "; give fluid.added_mass.semi_axes or a matrix, or model: none");
    }
  }
  return shift_added_mass(
      ellipsoid_added_mass(ellipsoid.semi_axes, surface_density),
      ellipsoid.X_BE.linear(), ellipsoid.X_BE.translation(), p_BBcm);
}

// The surface model with the overlap correction (header).
class SurfaceFluidForce : public ForceElement {
 public:
  SurfaceFluidForce(const HydrodynamicHull& hull, const HydrodynamicCoefficients& coefficients, const Ocean& ocean)
      : kernel_(hull.mesh_B, coefficients, hull.exposed),
        ocean_(ocean),
        excess_volume_(hull.excess_volume),
        p_BE_(hull.p_BE),
        excess_height_(2.0 * std::cbrt(3.0 * hull.excess_volume / (4.0 * kPi))) {}

  std::size_t faces() const { return kernel_.num_faces(); }

  void add(const ForceInput& in, StepWrench& out) override {
    const RigidBodyState& body = in.body;
    out.v_water_W = ocean_.current_W(in.p_WBcm, in.time);
    // Buoyancy, drag, friction, lift and Magnus from the faces, in the Ocean at the step's start time;
    // f_W acts at the centre of mass and tau_W is about it.
    BodyMotion motion;
    motion.X_WB = body.X_WB;
    motion.p_WBcm = in.p_WBcm;
    motion.v_WBcm = in.v_WBcm;
    motion.w_WB = body.w_WB;
    const OceanFluid water(ocean_, in.time);
    const HydrodynamicWrench fluid = kernel_.compute(motion, water);
    // The waves at the centre of mass, for the added mass: relative velocity and the water's acceleration.
    const FluidSampler::WavesNear waves = water.waves_near(in.p_WBcm);
    out.v_water_W += waves.velocity_W;
    out.a_water_W = waves.acceleration_W;
    out.f_W += fluid.f_W;
    out.tau_W += fluid.tau_W;
    out.submerged_fraction = fluid.wetted_area / kernel_.surface_area();
    if (excess_volume_ > 0.0) {
      // Overlapping parts: take back the doubly counted buoyancy, -rho g E, at the overlap's centroid,
      // ramped from dry to wet over its height (exact when it is fully submerged).
      const Eigen::Vector3d p_WE = body.X_WB * p_BE_;
      const double depth = ocean_.depth(p_WE.z());
      const double wet = std::clamp(0.5 + depth / excess_height_, 0.0, 1.0);
      // Buoyancy acts along +z of W with the Ocean's g, like the kernel's pressure.
      const Eigen::Vector3d f_E(0.0, 0.0, -wet * ocean_.density(std::max(depth, 0.0)) * excess_volume_ * ocean_.gravity());
      out.f_W += f_E;
      out.tau_W += (p_WE - in.p_WBcm).cross(f_E);
    }
  }

 private:
  SurfaceHydrodynamics kernel_;
  const Ocean& ocean_;
  double excess_volume_;   // E [m^3]
  Eigen::Vector3d p_BE_;   // its centroid in B
  double excess_height_;   // diameter of the sphere of volume E [m]
};

// The lumped model: buoyancy and damping relative to the current at the centre of mass.
class LumpedFluidForce : public ForceElement {
 public:
  LumpedFluidForce(const VehicleSpec& vehicle, const WorldSpec& world, const Ocean& ocean)
      : fluid_(vehicle, world), ocean_(ocean) {}

  void add(const ForceInput& in, StepWrench& out) override {
    out.v_water_W = ocean_.current_W(in.p_WBcm, in.time);
    const LumpedFluidWrench fluid = fluid_.wrench(in.body, out.v_water_W);
    out.f_W += fluid.f_W();
    out.tau_W += fluid.tau_W() + (in.body.X_WB.translation() - in.p_WBcm).cross(fluid.f_W());
    out.submerged_fraction = fluid.submerged_fraction;
  }

 private:
  LumpedFluid fluid_;
  const Ocean& ocean_;
};

}  // namespace

VehicleFluid make_vehicle_fluid(const VehicleSpec& vehicle, const WorldSpec& world, const Ocean& ocean,
                                const Eigen::Vector3d& p_BBcm) {
  VehicleFluid out;
  std::optional<HydrodynamicHull> hull;
  if (vehicle.fluid.model == FluidModelType::kSurface || geometry::has_surface_geometry(vehicle.links)) {
    hull = hydrodynamic_hull(vehicle);  // throws for a surface-model vehicle without faces
  }
  if (vehicle.fluid.model == FluidModelType::kSurface) {
    auto surface = std::make_unique<SurfaceFluidForce>(*hull, vehicle.fluid.hydrodynamics, ocean);
    out.faces = surface->faces();
    out.force = std::move(surface);
  } else {
    out.force = std::make_unique<LumpedFluidForce>(vehicle, world, ocean);
  }
  out.M_A0 = surface_added_mass(vehicle, hull ? &*hull : nullptr, p_BBcm, ocean.density(0.0));
  return out;
}

EarthRotationForce::EarthRotationForce(const WorldSpec& world, double mass)
    : Omega_W_(world.dynamics.earth_rotation_rate *
               Eigen::Vector3d(0.0, std::cos(world.origin.latitude_rad), std::sin(world.origin.latitude_rad))),
      mass_(mass) {}

void EarthRotationForce::add(const ForceInput& in, StepWrench& out) {
  out.f_W += -2.0 * mass_ * Omega_W_.cross(in.v_WBcm);
}

}  // namespace hadal::physics

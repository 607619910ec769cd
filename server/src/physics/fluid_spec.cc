#include "hadal/physics/fluid_spec.h"

#include <Eigen/Eigenvalues>

#include <string>

#include "hadal/config/key_table.h"
#include "hadal/config/vehicle_context.h"
#include "hadal/geometry/link_spec.h"
#include "hadal/geometry/primitive_mesh.h"

namespace hadal::physics {
namespace {

using namespace config::keys;
using config::VehicleContext;

const KeyTable<HydrodynamicCoefficients>& hydrodynamics_keys() {
  return declare_keys<HydrodynamicCoefficients>([](KeyTable<HydrodynamicCoefficients>& t) {
    t.describe("fluid.hydrodynamics", "the surface model's per-face coefficients");
    t.number("drag", &HydrodynamicCoefficients::drag).range(Range::non_negative())
        .doc("C_D of the per-face Newtonian drag (a sphere then has C_D = 0.5 on its frontal area)");
    t.number("skin_friction", &HydrodynamicCoefficients::skin_friction).range(Range::non_negative())
        .doc("C_f (turbulent flat plate, Re ~ 1e6 .. 1e7)");
    t.number("lift", &HydrodynamicCoefficients::lift).range(Range::non_negative())
        .doc("C_L (plate lift slope 2 C_L per radian)");
    t.number("magnus", &HydrodynamicCoefficients::magnus).unit("s").range(Range::non_negative())
        .doc("C_M of F = C_M rho A |v| (w x v); to be calibrated, 0 leaves it off");
  });
}

// A 6x6 added-mass matrix: symmetric (to rounding) and positive semidefinite.
bool read_added_mass_matrix(const Value& matrix, AddedMassSpec& added, NoContext&) {
  const auto values = matrix.numbers(36);
  if (!values) return false;
  const Matrix6d M = Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(values->data());
  const double scale = M.cwiseAbs().maxCoeff();
  const double asymmetry = (M - M.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > 1e-9 * scale) {
    matrix.error("must be symmetric (largest |M_ij - M_ji| = " + config::format_approximate(asymmetry) + ")");
    return false;
  }
  if (Eigen::SelfAdjointEigenSolver<Matrix6d>(M).eigenvalues().minCoeff() < -1e-9 * scale) {
    matrix.error("must be positive semidefinite (an added mass cannot lower the kinetic energy)");
    return false;
  }
  added.M_A0 = M;
  return true;
}

const KeyTable<AddedMassSpec>& added_mass_keys() {
  return declare_keys<AddedMassSpec>([](KeyTable<AddedMassSpec>& t) {
    t.describe("fluid.added_mass",
               "the fluid accelerated with the vehicle: M_A0 at the surface scaled by kappa(d) and the "
               "submerged fraction, with its Coriolis-centripetal terms");
    t.choice("model", &AddedMassSpec::model,
             {{"none", AddedMassModel::kNone},
              {"ellipsoid", AddedMassModel::kEllipsoid, "Lamb's coefficients of an ellipsoid"},
              {"matrix", AddedMassModel::kMatrix, "given"}})
        .selects("added_mass model")
        .default_text("`ellipsoid` (`none` for a vehicle without any link geometry)")
        .doc("how M_A0 is found");
    t.vector("semi_axes", &AddedMassSpec::semi_axes_E).only_for({"ellipsoid"}).unit("m").range(Range::positive())
        .default_text("fitted")
        .doc("without it: the hull's inertia-equivalent ellipsoid (same volume, centroid, principal axes and second "
             "moments of the enclosed volume; the hydrodynamic mesh must be closed)");
    t.pose("pose", &AddedMassSpec::X_BE).only_for({"ellipsoid"}).doc("with semi_axes: the ellipsoid's centre and axes in B");
    t.custom("matrix", read_added_mass_matrix,
             R"({"type": "array", "items": {"type": "number"}, "minItems": 36, "maxItems": 36})", "36 numbers")
        .only_for({"matrix"})
        .required_for({"matrix"}, "model 'matrix' needs the 6x6 added-mass matrix")
        .unit("kg, kg m, kg m²")
        .doc("row-major, symmetric, positive semidefinite; order [u v w p q r], magnitudes (Fossen's -X_udot ...)");
    t.vector("reference_point", &AddedMassSpec::p_BR).only_for({"matrix"}).unit("m")
        .doc("the point in B the matrix is taken about");
    t.boolean("coriolis", &AddedMassSpec::coriolis).only_for({"ellipsoid", "matrix"})
        .doc("the C_A(nu_r) nu_r terms (the Munk moment)");
    t.check([](const KeyReads& reads, AddedMassSpec&, NoContext&) {
      if (reads.has("pose") && !reads.has("semi_axes") && reads.ok("pose")) {
        reads.error_at_key("pose", "key 'pose' needs 'semi_axes' (without them the ellipsoid is fitted to the hull, "
                                   "centre and axes included)");
        return false;
      }
      return true;
    });
  });
}

}  // namespace

FluidSpec default_fluid(const std::vector<LinkSpec>& links) {
  FluidSpec fluid;
  const bool has_faces = geometry::has_surface_geometry(links);
  fluid.model = has_faces ? FluidModelType::kSurface : FluidModelType::kLumped;
  // Added mass is fitted to the hull by default; a vehicle without geometry has none unless given.
  fluid.added_mass.model = has_faces ? AddedMassModel::kEllipsoid : AddedMassModel::kNone;
  return fluid;
}

const KeyTable<FluidSpec, VehicleContext>& fluid_keys() {
  return declare_keys<FluidSpec, VehicleContext>([](KeyTable<FluidSpec, VehicleContext>& t) {
    t.describe("fluid", "the vehicle's fluid model: surface or lumped; added mass");
    t.choice("model", &FluidSpec::model,
             {{"lumped", FluidModelType::kLumped,
               "Fossen-style damping in the body frame and buoyancy at each link's buoyancy centre"},
              {"surface", FluidModelType::kSurface,
               "per-face pressure, drag, skin friction, lift on the links' meshes or collision shapes"}})
        .selects("fluid model")
        .default_text("`surface` if a link has a `mesh` or `collisions`, else `lumped`")
        .doc("the fluid model");
    t.vector("linear_damping", &FluidSpec::linear_damping).only_for({"lumped"}).range(Range::non_negative())
        .unit("N s/m (x3), N m s/rad (x3)").doc("X_u, Y_v, Z_w, K_p, M_q, N_r");
    t.vector("quadratic_damping", &FluidSpec::quadratic_damping).only_for({"lumped"}).range(Range::non_negative())
        .unit("N s²/m² (x3), N m s²/rad² (x3)").doc("X_u|u|, Y_v|v|, Z_w|w|, K_p|p|, M_q|q|, N_r|r|");
    t.map("hydrodynamics", &FluidSpec::hydrodynamics, hydrodynamics_keys()).only_for({"surface"})
        .doc("per-face coefficients");
    t.map("added_mass", &FluidSpec::added_mass, added_mass_keys())
        .doc("added mass and inertia; an ellipsoid fitted to the hull by default");
    t.unused_note([](const config::MapReader& map, const FluidSpec& fluid) -> std::string {
      if (map.has("model")) return "";
      return fluid.model == FluidModelType::kLumped
                 ? " (the default for a vehicle without a mesh or collision shapes)"
                 : " (the default for a vehicle with a mesh or collision shapes; set model: lumped for damping "
                   "coefficients)";
    });
    t.check([](const KeyReads& reads, FluidSpec& fluid, VehicleContext& context) {
      if (fluid.model != FluidModelType::kSurface || context.links == nullptr || context.links->empty()) return true;
      if (geometry::has_surface_geometry(*context.links) || !reads.has("model")) return true;
      reads.map().optional("model")->error(
          "fluid model 'surface' needs a hydrodynamic mesh: no link has a 'mesh' or 'collisions'");
      return false;
    });
  });
}

}  // namespace hadal::physics

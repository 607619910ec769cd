#include "hadal/geometry/link_spec.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "hadal/config/entry_keys.h"
#include "hadal/geometry/mesh_import.h"
#include "hadal/geometry/mesh_properties.h"
#include "hadal/geometry/mesh_transform.h"

namespace hadal {

const char* to_string(JointType type) {
  switch (type) {
    case JointType::kFixed: return "fixed";
    case JointType::kRevolute: return "revolute";
    case JointType::kContinuous: return "continuous";
    case JointType::kPrismatic: return "prismatic";
  }
  return "?";
}

bool link_moves(const std::vector<LinkSpec>& links, int index) {
  for (int i = index; i >= 0 && i < static_cast<int>(links.size()); i = links[static_cast<std::size_t>(i)].parent) {
    if (links[static_cast<std::size_t>(i)].joint.type != JointType::kFixed) return true;
  }
  return false;
}

Eigen::Isometry3d joint_motion(JointType type, const Eigen::Vector3d& axis, double q) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  switch (type) {
    case JointType::kRevolute:
    case JointType::kContinuous: X.linear() = Eigen::AngleAxisd(q, axis).toRotationMatrix(); break;
    case JointType::kPrismatic: X.translation() = q * axis; break;
    case JointType::kFixed: break;
  }
  return X;
}

bool limits_meet(const JointSpec& joint) {
  return (joint.type == JointType::kRevolute || joint.type == JointType::kPrismatic) && std::isfinite(joint.lower) &&
         joint.lower >= joint.upper;
}

void lock_joints(std::vector<LinkSpec>& links) {
  for (std::size_t i = 0; i < links.size(); ++i) {
    JointSpec& joint = links[i].joint;
    if (!limits_meet(joint)) continue;
    if (joint.lower != 0.0) {
      // The joint at its lock, in B: X_BL M(lower) X_BL^-1 moves the link and what hangs on it (the axis is in
      // the link's frame, through its origin).
      const Eigen::Isometry3d to_lock =
          links[i].X_BL * joint_motion(joint.type, joint.axis_L.normalized(), joint.lower) * links[i].X_BL.inverse();
      std::vector<char> beyond(links.size(), 0);
      beyond[i] = 1;
      for (std::size_t j = i; j < links.size(); ++j) {
        const int parent = links[j].parent;
        if (j > i) beyond[j] = parent >= static_cast<int>(i) ? beyond[static_cast<std::size_t>(parent)] : 0;
        if (beyond[j]) links[j].X_BL = to_lock * links[j].X_BL;
      }
    }
    joint.locked_type = joint.type;
    joint.type = JointType::kFixed;
    joint.initial = joint.lower;
  }
}

std::vector<int> link_bodies(const std::vector<LinkSpec>& links) {
  std::vector<int> body(links.size(), 0);
  int bodies = 1;
  for (std::size_t i = 0; i < links.size(); ++i) {
    const int parent = links[i].parent;
    const int parent_body = parent >= 0 && parent < static_cast<int>(i) ? body[static_cast<std::size_t>(parent)] : 0;
    body[i] = links[i].joint.type == JointType::kFixed ? parent_body : bodies++;
  }
  return body;
}

}  // namespace hadal

namespace hadal::geometry {
namespace {

using namespace config::keys;
using config::VehicleContext;

// Inertia tensors typed by hand are rounded to 3-4 digits; a 0.1 % tolerance on the triangle inequality
// still admits the limiting cases (thin rod, flat plate) written that way.
constexpr double kTriangleRelativeTolerance = 1e-3;

struct Inertia {
  double ixx = 0.0, iyy = 0.0, izz = 0.0, ixy = 0.0, ixz = 0.0, iyz = 0.0;
};

const KeyTable<Inertia>& inertia_keys() {
  return declare_keys<Inertia>([](KeyTable<Inertia>& t) {
    t.describe("links[].inertia",
               "I_LLcm_L about the centre of mass in L's axes, tensor entries as URDF/SDF; positive definite, "
               "principal moments obeying A + B >= C");
    using Field = std::pair<const char*, double Inertia::*>;
    for (const Field& f : {Field{"ixx", &Inertia::ixx}, Field{"iyy", &Inertia::iyy}, Field{"izz", &Inertia::izz}}) {
      t.number(f.first, f.second).required().unit("kg m²").range(Range::positive()).doc("moment");
    }
    for (const Field& f : {Field{"ixy", &Inertia::ixy}, Field{"ixz", &Inertia::ixz}, Field{"iyz", &Inertia::iyz}}) {
      t.number(f.first, f.second).unit("kg m²").doc("product");
    }
  });
}

bool read_inertia(const Value& value, LinkSpec& link, VehicleContext&) {
  Inertia in;
  if (!inertia_keys().read(value, &in)) return false;
  Eigen::Matrix3d I;
  I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  if (const std::string error = inertia_error(I); !error.empty()) {
    value.error(error);
    return false;
  }
  link.I_LLcm_L = I;
  return true;
}

const KeyTable<CollisionShape>& collision_keys() {
  return declare_keys<CollisionShape>([](KeyTable<CollisionShape>& t) {
    t.describe("links[].collisions[]", "a collision primitive; cylinders and capsules have their axis along G's z");
    t.choice("shape", &CollisionShape::type,
             {{"box", CollisionShapeType::kBox},
              {"sphere", CollisionShapeType::kSphere},
              {"cylinder", CollisionShapeType::kCylinder},
              {"capsule", CollisionShapeType::kCapsule}})
        .required()
        .selects("shape")
        .doc("the primitive");
    t.vector("size", &CollisionShape::box_size).only_for({"box"}).required_for({"box"}).unit("m")
        .range(Range::positive()).doc("full extents along G's x, y, z");
    t.number("radius", &CollisionShape::radius).only_for({"sphere", "cylinder", "capsule"})
        .required_for({"sphere", "cylinder", "capsule"}).unit("m").range(Range::positive()).doc("radius");
    t.number("length", &CollisionShape::length).only_for({"cylinder", "capsule"})
        .required_for({"cylinder", "capsule"}).unit("m").range(Range::positive())
        .doc("length of the cylindrical part (a capsule's total length is length + 2 radius)");
    t.pose("pose", &CollisionShape::X_LG).doc("X_LG, the shape's frame G in L");
  });
}

const KeyTable<LinkMesh>& link_mesh_keys() {
  return declare_keys<LinkMesh>([](KeyTable<LinkMesh>& t) {
    t.describe("links[].mesh", "a mesh file: GLB, glTF (+ .bin), OBJ, STL");
    t.file("file", &LinkMesh::file).required().doc("the mesh file");
    t.number("scale", [](LinkMesh& m) -> double& { return m.import.scale; }).range(Range::positive())
        .doc("file units to metres");
    t.choice("up_axis", [](LinkMesh& m) -> UpAxis& { return m.import.up_axis; },
             {{"z", UpAxis::kZ}, {"y", UpAxis::kY, "glTF's convention, rotated +90° about x into z up"}})
        .doc("the file's up axis");
    t.pose("pose", &LinkMesh::X_LM).doc("pose of the file's frame in L");
  });
}

// A link's mesh (YAML link.mesh or link.visual), through load_link_mesh: an import error is reported at
// its `file`, a bad volume at the map.
bool read_link_mesh(const Value& value, std::optional<LinkMesh>& out, bool volume_matters) {
  LinkMesh link_mesh;
  if (!link_mesh_keys().read(value, &link_mesh)) return false;
  const MeshLoad loaded = load_link_mesh(std::move(link_mesh), volume_matters, value.node()["file"].Scalar());
  if (!loaded.mesh) {
    if (loaded.at_file) {
      const YAML::Node file = value.node()["file"];
      value.in_same_file(file, config::child_path(value.path(), "file"), file.Mark()).error(loaded.error);
    } else {
      value.error(loaded.error);
    }
    return false;
  }
  out = std::move(loaded.mesh);
  return true;
}

const KeyTable<BuoyancySpec>& buoyancy_keys() {
  return declare_keys<BuoyancySpec>([](KeyTable<BuoyancySpec>& t) {
    t.describe("links[].buoyancy", "lumped buoyancy: the displaced volume of the submerged link");
    t.number("volume", &BuoyancySpec::volume).required().unit("m³").range(Range::non_negative()).doc("displaced volume");
    t.vector("center", &BuoyancySpec::p_LCb).unit("m").doc("centre of buoyancy in L");
  });
}

const KeyTable<CheckerboardSpec>& checkerboard_keys() {
  return declare_keys<CheckerboardSpec>([](KeyTable<CheckerboardSpec>& t) {
    t.describe("links[].appearance.checkerboard",
               "a calibration target: squares along x_P and y_P from P's origin, square (0, 0) "
               "dark, painted through the link's depth");
    t.custom(
         "squares",
         [](const Value& value, CheckerboardSpec& board, NoContext&) {
           const auto counts = value.numbers(2, Range::closed(2.0, 1000.0));
           if (!counts) return false;
           if ((*counts)[0] != std::floor((*counts)[0]) || (*counts)[1] != std::floor((*counts)[1])) {
             value.error("must be two whole numbers [columns, rows] (got [" + config::format_number((*counts)[0]) +
                         ", " + config::format_number((*counts)[1]) + "])");
             return false;
           }
           board.columns = static_cast<int>((*counts)[0]);
           board.rows = static_cast<int>((*counts)[1]);
           return true;
         },
         R"({"type": "array", "items": {"type": "integer", "minimum": 2, "maximum": 1000}, "minItems": 2, "maxItems": 2})",
         "2 integers")
        .required()
        .rule("whole numbers in [2, 1000]")
        .doc("[columns, rows]");
    t.number("square_size", &CheckerboardSpec::square_size).required().unit("m").range(Range::positive())
        .doc("side of a square");
    t.vector("dark_albedo", &CheckerboardSpec::dark_albedo).range(Range::closed(0.0, 1.0)).doc("of the dark squares");
    t.pose("pose", &CheckerboardSpec::X_LP).doc("the pattern frame P in L");
  });
}

const KeyTable<AppearanceSpec>& appearance_keys() {
  return declare_keys<AppearanceSpec>([](KeyTable<AppearanceSpec>& t) {
    t.describe("links[].appearance", "how cameras see the link and sonars hear it");
    t.vector("albedo", &AppearanceSpec::albedo).range(Range::closed(0.0, 1.0))
        .default_text("a mesh's glTF base colours, else `world.optics.vehicle_albedo`")
        .doc("per channel; replaces the mesh's colours");
    t.map("checkerboard", &AppearanceSpec::checkerboard, checkerboard_keys())
        .doc("a checkerboard painted on the link; outside it the link keeps `albedo`");
    t.number("backscatter_db", &AppearanceSpec::backscatter_db).unit("dB").range(Range::closed(-80.0, 0.0))
        .default_text("`world.acoustics.vehicle_backscatter_db`").doc("Lambert's mu for sonars");
  });
}

const KeyTable<JointSpec>& joint_keys() {
  return declare_keys<JointSpec>([](KeyTable<JointSpec>& t) {
    t.describe("links[].joint",
               "the joint to the parent link, at this link's origin (URDF's convention); q = 0 at `pose`");
    t.string("name", &JointSpec::name).default_text("the link's name")
        .doc("the joint's name in JointState and joint_controllers; unique among the vehicle's joints");
    t.choice("type", &JointSpec::type,
             {{"fixed", JointType::kFixed, "rigidly on the parent"},
              {"revolute", JointType::kRevolute, "turns about `axis` within its limits"},
              {"continuous", JointType::kContinuous, "turns about `axis` without limits"},
              {"prismatic", JointType::kPrismatic, "slides along `axis` within its limits"}})
        .required()
        .selects("joint type")
        .doc("how the link moves relative to its parent");
    t.vector("axis", &JointSpec::axis_L).only_for({"revolute", "continuous", "prismatic"})
        .doc("in the link's frame L (normalised); q > 0 turns right-handed about it or slides along it");
    t.number("lower_deg", &JointSpec::lower).only_for({"revolute"}).degrees().default_text("unlimited")
        .doc("lower limit of q");
    t.number("upper_deg", &JointSpec::upper).only_for({"revolute"}).degrees().default_text("unlimited")
        .doc("upper limit of q");
    t.number("lower", &JointSpec::lower).only_for({"prismatic"}).unit("m").default_text("unlimited")
        .doc("lower limit of q");
    t.number("upper", &JointSpec::upper).only_for({"prismatic"}).unit("m").default_text("unlimited")
        .doc("upper limit of q");
    t.number("initial_deg", &JointSpec::initial).only_for({"revolute", "continuous"}).degrees()
        .default_text("0 (or the nearer limit)").doc("q at the start and after a reset");
    t.number("initial", &JointSpec::initial).only_for({"prismatic"}).unit("m")
        .default_text("0 (or the nearer limit)").doc("q at the start and after a reset");
    t.number("damping", &JointSpec::damping).only_for({"revolute", "continuous", "prismatic"})
        .unit("N m s/rad or N s/m").range(Range::non_negative())
        .doc("viscous: a torque (force) -damping q_dot");
    t.number("friction", &JointSpec::friction).only_for({"revolute", "continuous", "prismatic"})
        .unit("N m or N").range(Range::non_negative())
        .doc("Coulomb: holds the joint against smaller torques (forces), opposes its motion with this one");
    t.number("effort_limit", &JointSpec::effort_limit).only_for({"revolute", "continuous", "prismatic"})
        .unit("N m or N").range(Range::positive()).default_text("unlimited")
        .doc("its motor's largest torque (force), whatever the command");
    t.number("velocity_limit", &JointSpec::velocity_limit).only_for({"revolute", "continuous", "prismatic"})
        .unit("rad/s or m/s").range(Range::positive()).default_text("unlimited")
        .doc("the largest rate a position or velocity command asks for");
    t.check([](const KeyReads& reads, JointSpec& joint, NoContext&) {
      if (joint.axis_L.norm() > 0.0) return true;
      reads.error_at_key("axis", "must not be zero");
      return false;
    });
    t.check([](const KeyReads& reads, JointSpec& joint, NoContext&) {
      if (!(joint.lower > joint.upper)) return true;
      reads.error_at_key(reads.has("upper_deg") ? "upper_deg" : "upper", "must not be below the lower limit");
      return false;
    });
    t.check([](const KeyReads& reads, JointSpec& joint, NoContext&) {
      if (joint.lower > joint.upper) return true;  // reported above
      // Not given: 0, or the nearer limit when both are on one side of it (a URDF mount's rule).
      if (!reads.has("initial") && !reads.has("initial_deg")) {
        joint.initial = std::max(joint.lower, std::min(0.0, joint.upper));
      }
      if (!(joint.initial < joint.lower || joint.initial > joint.upper)) return true;
      reads.error_at_key(reads.has("initial_deg") ? "initial_deg" : "initial", "must be within the joint's limits");
      return false;
    });
  });
}

}  // namespace

// A physical body has a positive-definite I whose principal moments satisfy the triangle inequalities
// A + B >= C (because A + B - C = 2 * integral of z^2 dm).
std::string inertia_error(const Eigen::Matrix3d& I) {
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
  if (!(moments.minCoeff() > 0.0)) {
    return "must be positive definite (principal moments " + config::format_approximate(moments[0]) + ", " +
           config::format_approximate(moments[1]) + ", " + config::format_approximate(moments[2]) + ")";
  }
  const double tolerance = kTriangleRelativeTolerance * moments.maxCoeff();
  // Diagonal entries obey the inequalities in any axes, so check them first for a readable message.
  const struct {
    double a, b, c;
    const char* text;
  } diagonal_checks[] = {{I(0, 0), I(1, 1), I(2, 2), "ixx + iyy >= izz"},
                         {I(1, 1), I(2, 2), I(0, 0), "iyy + izz >= ixx"},
                         {I(2, 2), I(0, 0), I(1, 1), "izz + ixx >= iyy"}};
  for (const auto& check : diagonal_checks) {
    if (check.a + check.b < check.c - tolerance) {
      return std::string("violates the triangle inequality ") + check.text + " (" + config::format_number(check.a) +
             " + " + config::format_number(check.b) + " < " + config::format_number(check.c) + ")";
    }
  }
  // Eigenvalues are sorted ascending: the binding inequality is m0 + m1 >= m2.
  if (moments[0] + moments[1] < moments[2] - tolerance) {
    return "violates the triangle inequality for principal moments (" + config::format_approximate(moments[0]) +
           " + " + config::format_approximate(moments[1]) + " < " + config::format_approximate(moments[2]) + ")";
  }
  return "";
}

MeshLoad load_link_mesh(LinkMesh link_mesh, bool volume_matters, const std::string& written) {
  MeshLoad result;
  ImportResult imported = import_mesh(link_mesh.file, link_mesh.import);
  if (!imported.mesh) {
    result.error = imported.error;
    result.at_file = true;
    return result;
  }
  TriangleMesh& mesh = *imported.mesh;
  transform_mesh(link_mesh.X_LM, &mesh);
  const MeshProperties properties = compute_mesh_properties(mesh);
  link_mesh.closed = properties.closed;
  link_mesh.volume = properties.volume;
  link_mesh.p_LMc = properties.centroid;
  link_mesh.I_unit_density = properties.inertia_unit_density;
  link_mesh.boundary_edges = properties.boundary_edges;
  link_mesh.mesh = std::make_shared<const TriangleMesh>(std::move(mesh));
  if (volume_matters && properties.closed && !(properties.volume > 0.0)) {
    result.error = "mesh " + config::quoted(written) + " encloses a volume of " +
                   config::format_approximate(properties.volume) + " m^3 (faces oriented inward?)";
    return result;
  }
  result.mesh = std::move(link_mesh);
  return result;
}

const KeyTable<LinkSpec, VehicleContext>& link_keys() {
  return declare_keys<LinkSpec, VehicleContext>([](KeyTable<LinkSpec, VehicleContext>& t) {
    t.describe("links[]", "a rigid body of the vehicle: on the base link, or on a `parent` through a `joint`");
    config::declare_name_key(t, "link", &LinkSpec::name).doc("unique within the vehicle");
    t.custom(
         "parent",
         [](const Value& value, LinkSpec& link, VehicleContext& c) {
           const auto name = value.string();
           if (!name) return false;
           if (!c.link_names) return true;  // an earlier link was unusable (reported already)
           const std::vector<std::string>& earlier = *c.link_names;
           if (earlier.empty()) {
             value.error("links[0] is the base link: it has no parent");
             return false;
           }
           const auto it = std::find(earlier.begin(), earlier.end(), *name);
           if (it == earlier.end()) {
             value.error("no earlier link named " + config::quoted(*name) +
                         " (a parent comes before its children in `links`" +
                         "; earlier: " + config::join_names(earlier) + ")");
             return false;
           }
           link.parent = static_cast<int>(it - earlier.begin());
           return true;
         },
         config::kNameSchema, "string")
        .default_text("the base link (links[0])")
        .doc("the link this one hangs on, through `joint`; not for links[0]");
    t.pose("pose", &LinkSpec::X_BL)
        .doc("X_BL, the link frame L in B; with `parent`, X_PL in the parent's frame (at q = 0 of every joint)");
    t.map("joint", &LinkSpec::joint, joint_keys()).default_text("fixed")
        .doc("how the link moves relative to its parent (or B); not for links[0]");
    t.custom(
         "mesh", [](const Value& value, LinkSpec& link, VehicleContext&) { return read_link_mesh(value, link.mesh, true); },
         "", "map")
        .keys_of(link_mesh_keys())
        .doc("the link's surface from a mesh file (fluid forces, soil, ray casts; mass and buoyancy of a closed one)");
    t.number("density", &LinkSpec::density).unit("kg/m³").range(Range::positive())
        .default_text("none")
        .doc("needs a closed `mesh`: mass = density x volume, centre of mass its centroid, inertia of the homogeneous "
             "solid; not with `mass`, `center_of_mass`, `inertia`");
    t.number("mass", &LinkSpec::mass).required().unless("density").unit("kg").range(Range::positive())
        .default_text("required (unless `density`)").doc("the link's mass");
    t.vector("center_of_mass", &LinkSpec::p_LLcm).unless("density").unit("m").doc("p_LLcm, in L");
    t.custom("inertia", read_inertia, "", "map").keys_of(inertia_keys()).required().unless("density")
        .default_text("required (unless `density`)").unit("kg m²").doc("about the centre of mass, in L's axes");
    t.list("collisions", &LinkSpec::collisions, collision_keys()).doc("collision shapes");
    t.number("friction", &LinkSpec::friction).range(Range::closed(0.0, 2.0))
        .doc("Coulomb friction coefficient of its surface in rigid contact; a contact's is the product of its two "
             "surfaces' (the seabed's is 0.8); a body's is its first link's (a gripper's pads: about 1)");
    t.map("buoyancy", &LinkSpec::buoyancy, buoyancy_keys())
        .default_text("volume 0, or the closed `mesh`'s volume")
        .doc("lumped buoyancy (the lumped fluid model; the surface model integrates pressure instead)");
    t.custom(
         "visual",
         [](const Value& value, LinkSpec& link, VehicleContext&) { return read_link_mesh(value, link.visual, false); },
         "", "map")
        .keys_of(link_mesh_keys())
        .doc("how the link looks to ray casts in place of its surface (open meshes are fine); the physics keeps "
             "`mesh` or `collisions`, mass and buoyancy ignore it");
    t.map("appearance", &LinkSpec::appearance, appearance_keys()).doc("how cameras and sonars see the link");
    t.check([](const KeyReads& reads, LinkSpec&, VehicleContext& c) {
      if (!reads.has("joint") || !c.link_names || !c.link_names->empty()) return true;
      reads.error_at_key("joint", "links[0] is the base link: it has no joint");
      return false;
    });
    t.check([](const KeyReads& reads, LinkSpec& link, VehicleContext&) {
      bool ok = true;
      if (reads.has("density") && reads.ok("density")) {
        const double density = link.density;
        if (!reads.has("mesh")) {
          reads.error_at_key("density", "key 'density' needs 'mesh' (mass properties from the mesh's volume)");
          ok = false;
        } else if (link.mesh && !link.mesh->closed) {
          reads.map().optional("mesh")->error("mesh is open (" + std::to_string(link.mesh->boundary_edges) +
                                              " boundary edges): mass from 'density' needs a closed mesh");
          ok = false;
        } else if (link.mesh) {
          // Mass properties of the homogeneous solid the mesh encloses, already in L.
          link.mass = density * link.mesh->volume;
          link.p_LLcm = link.mesh->p_LMc;
          link.I_LLcm_L = density * link.mesh->I_unit_density;
        }
        for (const char* key : {"mass", "center_of_mass", "inertia"}) {
          if (reads.has(key)) {
            reads.error_at_key(key, std::string("key '") + key +
                                        "' cannot be combined with 'density' (the mesh and density give it)");
            ok = false;
          }
        }
      }
      if (!reads.has("buoyancy") && link.mesh) {
        // A hull mesh displaces the volume it encloses, centred on its centroid.
        if (link.mesh->closed) {
          link.buoyancy.volume = link.mesh->volume;
          link.buoyancy.p_LCb = link.mesh->p_LMc;
        } else {
          reads.map().optional("mesh")->warn(
              "mesh is open (" + std::to_string(link.mesh->boundary_edges) +
              " boundary edges): its volume is undefined, so the link gets no buoyancy; give buoyancy: {volume, "
              "center} or close the mesh");
        }
      }
      return ok;
    });
  });
}

}  // namespace hadal::geometry

#include "hadal/config/urdf_import.h"

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <regex>
#include <sstream>
#include <utility>

#include "hadal/config/key_table.h"
#include "hadal/config/vehicle_context.h"
#include "hadal/config/yaml_reader.h"

namespace hadal::config {

namespace {

constexpr const char* kInitialSchema = R"({"type": "object", "additionalProperties": {"type": "number"}})";

// `initial_deg` or `initial`: joint name -> position.
bool read_initial(const Value& value, bool angle, UrdfMount& mount) {
  if (!value.node().IsMap()) {
    value.error("must be a map of joint names to numbers (got " + value.describe() + ")");
    return false;
  }
  bool ok = true;
  for (const auto& entry : value.node()) {
    const std::string name = entry.first.Scalar();
    const Value item = value.in_same_file(entry.second, child_path(value.path(), name), entry.second.Mark());
    const std::optional<double> number = item.number();
    if (!number) {
      ok = false;
      continue;
    }
    mount.initial.push_back({name, angle ? *number * 3.14159265358979323846 / 180.0 : *number, angle});
  }
  return ok;
}

}  // namespace

const KeyTable<UrdfMount, VehicleContext>& urdf_keys() {
  return declare_keys<UrdfMount, VehicleContext>([](KeyTable<UrdfMount, VehicleContext>& t) {
    t.describe("urdf",
               "links, joints, inertials, collision shapes and meshes from a URDF file (docs/ARCHITECTURE.md, "
               "\"URDF import\"); the YAML adds the fluid model, sensors, actuators and joint controllers");
    t.file("file", &UrdfMount::file).required().doc("the URDF file");
    t.string("root", &UrdfMount::root)
        .default_text("the URDF's root link")
        .doc("the URDF link to start at: it and the links below it are imported (leave out a `world` link)");
    t.string("parent", &UrdfMount::parent)
        .default_text("links[0]")
        .doc("with `links`: the link the root hangs on, by a fixed joint");
    t.pose("pose", &UrdfMount::X_PR)
        .doc(
            "the root link's frame in `parent`'s (without `links`: in the body frame B, the root being the base link)");
    t.custom(
         "initial_deg", [](const Value& value, UrdfMount& m, VehicleContext&) { return read_initial(value, true, m); },
         kInitialSchema, "map of joint names to numbers")
        .unit("deg")
        .default_text("0 (or the nearer limit)")
        .doc("where revolute and continuous joints start, by name: {elbow: -30, ...}");
    t.custom(
         "initial", [](const Value& value, UrdfMount& m, VehicleContext&) { return read_initial(value, false, m); },
         kInitialSchema, "map of joint names to numbers")
        .unit("m")
        .default_text("0 (or the nearer limit)")
        .doc("where prismatic joints start, by name");
  });
}

namespace {

namespace fs = std::filesystem;

// urdfdom reports through console_bridge: its messages are collected while one file is parsed (the
// handler is process-wide, hence the lock).
class CollectMessages : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN)
      messages.push_back({text, level == console_bridge::CONSOLE_BRIDGE_LOG_WARN});
  }
  struct Message {
    std::string text;
    bool warning;
  };
  std::vector<Message> messages;
};

std::string escape_regex(const std::string& text) {
  static const std::regex special(R"([.^$|()\[\]{}*+?\\])");
  return std::regex_replace(text, special, R"(\$&)");
}

// Where in the URDF's text an element is: 1-based line and column of `<tag ... name="name"`, or 0.
struct Place {
  int line = 0;
  int column = 0;
};

class UrdfText {
 public:
  explicit UrdfText(std::string text) : text_(std::move(text)) {}
  const std::string& text() const { return text_; }

  Place find(const std::string& tag, const std::string& name) const {
    const std::regex element("<" + tag + R"(\s[^>]*name\s*=\s*["'])" + escape_regex(name) + R"(["'])");
    std::smatch match;
    if (!std::regex_search(text_, match, element)) return {};
    return place_of(static_cast<std::size_t>(match.position(0)));
  }

 private:
  Place place_of(std::size_t offset) const {
    Place p;
    p.line = 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
    const std::size_t line_start = text_.rfind('\n', offset == 0 ? 0 : offset - 1);
    p.column = static_cast<int>(offset - (line_start == std::string::npos ? 0 : line_start + 1)) + 1;
    return p;
  }
  std::string text_;
};

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  X.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return X;
}

Eigen::Vector3d to_vector(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

class Importer {
 public:
  Importer(const Value& where, const UrdfMount& mount, UrdfText text)
      : where_(where), mount_(mount), text_(std::move(text)) {}

  bool run(int parent_index, std::vector<LinkSpec>* links);

 private:
  // A problem at the element <tag name="name">, in the URDF at its line.
  void report(const std::string& tag, const std::string& name, const std::string& message, bool warning) {
    const Place p = text_.find(tag, name);
    where_.report_in(mount_.file, p.line, p.column, tag + " " + config::quoted(name), message, warning);
    if (!warning) ok_ = false;
  }
  void error(const std::string& tag, const std::string& name, const std::string& message) {
    report(tag, name, message, false);
  }
  void warn(const std::string& tag, const std::string& name, const std::string& message) {
    report(tag, name, message, true);
  }
  // Gazebo's friction of each link that has one (<gazebo reference="link"><mu1>), which urdfdom skips.
  void read_gazebo_friction();
  // Fill *spec from the element; problems are reported (ok_).
  void import_link(const urdf::Link& link, LinkSpec* spec);
  void import_joint(const urdf::Joint& joint, JointSpec* spec);
  std::optional<LinkMesh> import_mesh(const urdf::Link& link, const urdf::Mesh& mesh, const urdf::Pose& origin,
                                      bool volume_matters);
  // The file a mesh's filename names, or "" (reported).
  std::string mesh_path(const std::string& link, const std::string& filename);

  const Value& where_;
  const UrdfMount& mount_;
  UrdfText text_;
  std::map<std::string, double> friction_;  // read_gazebo_friction's, by link name
  bool ok_ = true;
};

std::string Importer::mesh_path(const std::string& link, const std::string& filename) {
  const fs::path urdf_dir = fs::path(mount_.file).parent_path();
  fs::path path;
  const std::string package = "package://";
  const std::string file_uri = "file://";
  if (filename.rfind(package, 0) == 0) {
    const std::string rest = filename.substr(package.size());
    const std::size_t slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
    std::vector<fs::path> candidates;
    std::error_code ec;
    // The package's own directory above the URDF (a URDF in PKG/urdf/ names PKG/meshes/...), then the roots.
    for (fs::path dir = fs::absolute(urdf_dir, ec); !dir.empty(); dir = dir.parent_path()) {
      if (dir.filename() == name) candidates.push_back(dir / inside);
      if (dir == dir.parent_path()) break;
    }
    if (const auto* roots = where_.roots()) {
      for (const fs::path& root : *roots) candidates.push_back(root / name / inside);
    }
    for (const fs::path& candidate : candidates) {
      if (fs::exists(candidate, ec)) {
        path = candidate;
        break;
      }
    }
    if (path.empty()) {
      error("link", link,
            "mesh " + config::quoted(filename) + ": no directory named " + config::quoted(name) +
                " above the URDF or in an asset root holds " + config::quoted(inside) +
                " (hadald --asset-root DIR adds the directory holding " + config::quoted(name) + ")");
      return "";
    }
  } else if (filename.rfind(file_uri, 0) == 0) {
    path = filename.substr(file_uri.size());
  } else {
    path = urdf_dir / filename;
  }
  const std::string refusal = where_.file_refusal(path, filename);
  if (!refusal.empty()) {
    error("link", link, "mesh " + refusal);
    return "";
  }
  return path.string();
}

std::optional<LinkMesh> Importer::import_mesh(const urdf::Link& link, const urdf::Mesh& mesh, const urdf::Pose& origin,
                                              bool volume_matters) {
  if (mesh.scale.x != mesh.scale.y || mesh.scale.y != mesh.scale.z || !(mesh.scale.x > 0.0)) {
    error("link", link.name,
          "mesh " + config::quoted(mesh.filename) + ": scale must be uniform and positive (got " +
              format_number(mesh.scale.x) + " " + format_number(mesh.scale.y) + " " + format_number(mesh.scale.z) +
              ")");
    return std::nullopt;
  }
  LinkMesh spec;
  spec.file = mesh_path(link.name, mesh.filename);
  if (spec.file.empty()) return std::nullopt;
  spec.import.scale = mesh.scale.x;
  spec.X_LM = to_isometry(origin);
  geometry::MeshLoad loaded = geometry::load_link_mesh(std::move(spec), volume_matters, mesh.filename);
  if (!loaded.mesh) error("link", link.name, loaded.error);
  return std::move(loaded.mesh);
}

void Importer::read_gazebo_friction() {
  TiXmlDocument document;
  document.Parse(text_.text().c_str());
  const TiXmlElement* robot = document.RootElement();
  if (robot == nullptr) return;
  for (const TiXmlElement* gazebo = robot->FirstChildElement("gazebo"); gazebo != nullptr;
       gazebo = gazebo->NextSiblingElement("gazebo")) {
    const char* reference = gazebo->Attribute("reference");
    const TiXmlElement* mu1 = gazebo->FirstChildElement("mu1");
    if (reference == nullptr || mu1 == nullptr || mu1->GetText() == nullptr) continue;
    char* end = nullptr;
    const double mu = std::strtod(mu1->GetText(), &end);
    if (end == mu1->GetText() || !(mu >= 0.0 && mu <= 2.0)) {
      error("link", reference, std::string("gazebo mu1 must be a number in [0, 2] (got '") + mu1->GetText() + "')");
      continue;
    }
    friction_[reference] = mu;
  }
}

void Importer::import_link(const urdf::Link& link, LinkSpec* spec) {
  spec->name = link.name;
  if (const auto it = friction_.find(link.name); it != friction_.end()) spec->friction = it->second;
  spec->mass = 0.0;
  spec->I_LLcm_L.setZero();
  if (link.inertial) {
    const urdf::Inertial& in = *link.inertial;
    if (!(in.mass > 0.0) || !std::isfinite(in.mass)) {
      error("link", link.name, "inertial mass must be positive (got " + format_number(in.mass) + ")");
    }
    Eigen::Matrix3d I;
    I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    if (const std::string problem = geometry::inertia_error(I); !problem.empty()) {
      error("link", link.name, "inertia " + problem);
    }
    const Eigen::Isometry3d X_LI = to_isometry(in.origin);  // the inertial frame in L
    spec->mass = in.mass;
    spec->p_LLcm = X_LI.translation();
    spec->I_LLcm_L = X_LI.linear() * I * X_LI.linear().transpose();
  }
  for (const urdf::CollisionSharedPtr& collision : link.collision_array) {
    if (!collision || !collision->geometry) continue;
    const urdf::Geometry& geometry = *collision->geometry;
    CollisionShape shape;
    shape.X_LG = to_isometry(collision->origin);
    switch (geometry.type) {
      case urdf::Geometry::BOX:
        shape.type = CollisionShapeType::kBox;
        shape.box_size = to_vector(static_cast<const urdf::Box&>(geometry).dim);
        break;
      case urdf::Geometry::SPHERE:
        shape.type = CollisionShapeType::kSphere;
        shape.radius = static_cast<const urdf::Sphere&>(geometry).radius;
        break;
      case urdf::Geometry::CYLINDER:
        shape.type = CollisionShapeType::kCylinder;
        shape.radius = static_cast<const urdf::Cylinder&>(geometry).radius;
        shape.length = static_cast<const urdf::Cylinder&>(geometry).length;
        break;
      case urdf::Geometry::MESH: {
        if (spec->mesh) {
          error("link", link.name, "has more than one collision mesh; Hadal takes one mesh per link as its surface");
          continue;
        }
        std::optional<LinkMesh> mesh =
            import_mesh(link, static_cast<const urdf::Mesh&>(geometry), collision->origin, true);
        if (mesh) spec->mesh = std::move(mesh);
        continue;
      }
    }
    const bool positive = shape.type == CollisionShapeType::kBox
                              ? (shape.box_size.array() > 0.0).all()
                              : shape.radius > 0.0 && (shape.type == CollisionShapeType::kSphere || shape.length > 0.0);
    if (!positive) {
      error("link", link.name, "collision shape with a zero or negative size");
      continue;
    }
    spec->collisions.push_back(shape);
  }
  // A closed collision mesh displaces its volume (the lumped fluid model; the surface model integrates
  // pressure over it instead).
  if (spec->mesh && spec->mesh->closed) {
    spec->buoyancy.volume = spec->mesh->volume;
    spec->buoyancy.p_LCb = spec->mesh->p_LMc;
  }
  for (const urdf::VisualSharedPtr& visual : link.visual_array) {
    if (!visual) continue;
    if (visual->material && !spec->appearance.albedo && visual->material->texture_filename.empty()) {
      const urdf::Color& c = visual->material->color;
      spec->appearance.albedo = Eigen::Array3d(c.r, c.g, c.b).cwiseMax(0.0).cwiseMin(1.0);
    }
    if (!visual->geometry || visual->geometry->type != urdf::Geometry::MESH) continue;
    if (spec->visual) {
      warn("link", link.name, "has more than one visual mesh: ray casts see the first");
      continue;
    }
    spec->visual = import_mesh(link, static_cast<const urdf::Mesh&>(*visual->geometry), visual->origin, false);
  }
}

void Importer::import_joint(const urdf::Joint& joint, JointSpec* spec) {
  spec->name = joint.name;
  switch (joint.type) {
    case urdf::Joint::FIXED:
      spec->type = JointType::kFixed;
      return;
    case urdf::Joint::REVOLUTE:
      spec->type = JointType::kRevolute;
      break;
    case urdf::Joint::CONTINUOUS:
      spec->type = JointType::kContinuous;
      break;
    case urdf::Joint::PRISMATIC:
      spec->type = JointType::kPrismatic;
      break;
    case urdf::Joint::FLOATING:
    case urdf::Joint::PLANAR:
    case urdf::Joint::UNKNOWN:
      error("joint", joint.name,
            std::string("type ") +
                (joint.type == urdf::Joint::FLOATING ? "floating"
                 : joint.type == urdf::Joint::PLANAR ? "planar"
                                                     : "unknown") +
                " is not supported (fixed, revolute, continuous, prismatic); a vehicle's base floats already");
      return;
  }
  spec->axis_L = to_vector(joint.axis);
  if (!(spec->axis_L.norm() > 0.0)) error("joint", joint.name, "axis must not be zero");
  if (joint.limits) {
    const urdf::JointLimits& limits = *joint.limits;
    if (spec->type != JointType::kContinuous) {
      spec->lower = limits.lower;
      spec->upper = limits.upper;
      if (limits.lower > limits.upper) {
        error("joint", joint.name,
              "limit upper " + format_number(limits.upper) + " is below lower " + format_number(limits.lower));
      }
    }
    // URDF's effort and velocity are the motor's limits; 0 (a joint without a motor) stays 0.
    if (limits.effort < 0.0 || limits.velocity < 0.0) {
      error("joint", joint.name, "limit effort and velocity must not be negative");
    }
    spec->effort_limit = std::max(limits.effort, 0.0);
    spec->velocity_limit = std::max(limits.velocity, 0.0);
  }
  spec->initial = std::clamp(0.0, std::min(spec->lower, spec->upper), spec->upper);
  if (joint.dynamics) {
    spec->damping = joint.dynamics->damping;
    spec->friction = joint.dynamics->friction;
    if (spec->damping < 0.0 || spec->friction < 0.0) {
      error("joint", joint.name, "dynamics damping and friction must not be negative");
    }
  }
  if (joint.mimic) {
    warn(
        "joint", joint.name,
        "mimics " + config::quoted(joint.mimic->joint_name) + ": Hadal does not couple it, the joint moves on its own");
  }
}

bool Importer::run(int parent_index, std::vector<LinkSpec>* links) {
  static std::mutex console_lock;
  urdf::ModelInterfaceSharedPtr model;
  CollectMessages collect;
  {
    const std::lock_guard<std::mutex> lock(console_lock);
    console_bridge::useOutputHandler(&collect);
    model = urdf::parseURDF(text_.text());
    console_bridge::restorePreviousOutputHandler();
  }
  for (const CollectMessages::Message& message : collect.messages) {
    // urdfdom names elements in brackets ("child link [x] of joint [y] not found"): the first that is
    // in the file places the message.
    static const std::regex bracketed(R"(\[([^\]]+)\])");
    Place p;
    std::string path = "robot";
    for (auto it = std::sregex_iterator(message.text.begin(), message.text.end(), bracketed);
         it != std::sregex_iterator() && p.line == 0; ++it) {
      for (const char* tag : {"joint", "link", "material"}) {
        p = text_.find(tag, (*it)[1].str());
        if (p.line > 0) {
          path = std::string(tag) + " " + config::quoted((*it)[1].str());
          break;
        }
      }
    }
    where_.report_in(mount_.file, p.line, p.column, path, "urdfdom: " + message.text, message.warning);
    if (!message.warning) ok_ = false;
  }
  if (!model) {
    if (ok_) where_.report_in(mount_.file, 0, 0, "robot", "urdfdom could not read the file as a URDF");
    return false;
  }
  read_gazebo_friction();
  urdf::LinkConstSharedPtr root = model->getRoot();
  if (!mount_.root.empty()) {
    root = model->getLink(mount_.root);
    if (!root) {
      std::vector<urdf::LinkSharedPtr> all;
      model->getLinks(all);
      std::vector<std::string> names;
      for (const auto& link : all) names.push_back(link->name);
      std::sort(names.begin(), names.end());
      where_.in_same_file(where_.node()["root"], child_path(where_.path(), "root"), where_.node()["root"].Mark())
          .error("no link named " + config::quoted(mount_.root) + " in " +
                 config::quoted(fs::path(mount_.file).filename().string()) + " (links: " + join_names(names) + ")");
      return false;
    }
  }
  if (!root->inertial) {
    for (const urdf::JointSharedPtr& joint : root->child_joints) {
      if (joint->type == urdf::Joint::FIXED) continue;
      error("link", root->name,
            "the root link has no inertial and its joint " + config::quoted(joint->name) +
                " moves: it is not part of a "
                "vehicle (Gazebo's `world`?); give urdf.root, the link to start at (" +
                config::quoted(joint->child_link_name) + "?)");
      return false;
    }
  }

  struct Pending {
    urdf::LinkConstSharedPtr link;
    int parent;  // index in *links; -1 for the root
  };
  std::vector<Pending> stack{{root, -1}};
  while (!stack.empty()) {
    const Pending item = stack.back();
    stack.pop_back();
    LinkSpec spec = geometry::link_keys().defaults();
    import_link(*item.link, &spec);
    if (item.parent < 0) {
      spec.parent = links->empty() ? -1 : parent_index;
      spec.X_BL = links->empty() ? mount_.X_PR : (*links)[static_cast<std::size_t>(parent_index)].X_BL * mount_.X_PR;
    } else {
      spec.parent = item.parent;
      const urdf::Joint& joint = *item.link->parent_joint;
      import_joint(joint, &spec.joint);
      spec.X_BL =
          (*links)[static_cast<std::size_t>(item.parent)].X_BL * to_isometry(joint.parent_to_joint_origin_transform);
    }
    const int index = static_cast<int>(links->size());
    links->push_back(std::move(spec));
    // Children in the file's order (the stack takes them in reverse).
    for (auto it = item.link->child_links.rbegin(); it != item.link->child_links.rend(); ++it) {
      stack.push_back({*it, index});
    }
  }
  return ok_;
}

}  // namespace

namespace {

// `initial_deg` and `initial` onto the imported links' joints (from index `first` on), each reported at its
// YAML entry: a joint the URDF does not have, of the other kind, or outside its limits.
bool apply_initial(const Value& where, const UrdfMount& mount, std::size_t first, std::vector<LinkSpec>* links) {
  bool ok = true;
  for (const UrdfMount::Initial& initial : mount.initial) {
    const char* key = initial.angle ? "initial_deg" : "initial";
    const YAML::Node node = where.node()[key][initial.joint];
    const Value item = where.in_same_file(node, child_path(child_path(where.path(), key), initial.joint), node.Mark());
    const auto it = std::find_if(
        links->begin() + static_cast<std::ptrdiff_t>(first), links->end(),
        [&](const LinkSpec& l) { return l.joint.type != JointType::kFixed && l.joint.name == initial.joint; });
    if (it == links->end()) {
      item.error("the URDF has no moving joint named " + config::quoted(initial.joint));
      ok = false;
      continue;
    }
    JointSpec& joint = it->joint;
    if ((joint.type == JointType::kPrismatic) == initial.angle) {
      item.error(std::string("joint ") + config::quoted(initial.joint) + " is " + to_string(joint.type) +
                 ": its start goes in `" + (initial.angle ? "initial" : "initial_deg") + "`");
      ok = false;
      continue;
    }
    if (initial.value < joint.lower || initial.value > joint.upper) {
      item.error("must be within the joint's limits");
      ok = false;
      continue;
    }
    joint.initial = initial.value;
  }
  return ok;
}

}  // namespace

bool import_urdf(const Value& where, const UrdfMount& mount, int parent_index, std::vector<LinkSpec>* links) {
  std::ifstream in(mount.file, std::ios::binary);
  const YAML::Node file = where.node()["file"];
  const Value file_value = where.in_same_file(file, child_path(where.path(), "file"), file.Mark());
  if (!in) {
    file_value.error("cannot open " + config::quoted(mount.file));
    return false;
  }
  std::ostringstream text;
  text << in.rdbuf();
  const std::size_t first = links->size();
  Importer importer(where, mount, UrdfText(text.str()));
  return importer.run(parent_index, links) && apply_initial(where, mount, first, links);
}

}  // namespace hadal::config

#include "scene_message.h"

#include "hadal/dds/time_msg.h"
#include "hadal/geometry/primitive_mesh.h"
#include "hadal/geometry/seabed_height.h"
#include "hadal/physics/articulation.h"
#include "hadal/physics/ocean.h"
#include "hadal/sensors/sensor_kinds.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <type_traits>

namespace hadal::dds {
namespace {

void set_color(const Eigen::Array3d& albedo, std_msgs::msg::ColorRGBA& color) {
  color.r(static_cast<float>(albedo[0]));
  color.g(static_cast<float>(albedo[1]));
  color.b(static_cast<float>(albedo[2]));
  color.a(1.0f);
}

void set_pose(const Eigen::Isometry3d& X, geometry_msgs::msg::Pose& pose) {
  const Eigen::Quaterniond q(X.linear());
  pose.position().x(X.translation().x());
  pose.position().y(X.translation().y());
  pose.position().z(X.translation().z());
  pose.orientation().x(q.x());
  pose.orientation().y(q.y());
  pose.orientation().z(q.z());
  pose.orientation().w(q.w());
}

void copy_mesh(const geometry::TriangleMesh& mesh, hadal_msgs::msg::SceneMesh& out) {
  out.positions(mesh.positions);
  out.indices(mesh.indices);
}

// The plane as a square of side kPlaneSide centred under the vehicles' mean start position.
void plane_mesh(const Model& model, double z, hadal_msgs::msg::SceneMesh& out) {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const VehicleSpec& vehicle : model.vehicles) centre += vehicle.X_WB_initial.translation().head<2>();
  if (!model.vehicles.empty()) centre /= static_cast<double>(model.vehicles.size());
  const double h = 0.5 * kPlaneSide;
  std::vector<float> positions;
  for (const auto& [dx, dy] : {std::pair{-h, -h}, std::pair{h, -h}, std::pair{h, h}, std::pair{-h, h}}) {
    positions.insert(positions.end(), {static_cast<float>(centre.x() + dx), static_cast<float>(centre.y() + dy),
                                       static_cast<float>(z)});
  }
  out.positions(positions);
  out.indices({0, 1, 2, 0, 2, 3});
}

// A large seabed mesh as its top surface sampled on a grid over its xy extent: vertices where the seabed
// is, two triangles per cell whose four corners all have one.
void resampled_mesh(const geometry::TriangleMesh& mesh, hadal_msgs::msg::SceneMesh& out) {
  Eigen::AlignedBox2d box;
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    box.extend(Eigen::Vector2d(mesh.positions[3 * i], mesh.positions[3 * i + 1]));
  }
  const Eigen::Vector2d size = box.sizes();
  // A mesh with no horizontal extent (a wall, seen from above) has no top surface to sample.
  if (!(std::max(size.x(), size.y()) > 0.0)) return;
  const double cell = std::max(size.x(), size.y()) / kSeabedGrid;
  const int nx = std::max(1, static_cast<int>(std::ceil(size.x() / cell))) + 1;
  const int ny = std::max(1, static_cast<int>(std::ceil(size.y() / cell))) + 1;
  const geometry::SeabedHeight height(mesh);
  std::vector<float> positions;
  std::vector<std::uint32_t> vertex(static_cast<std::size_t>(nx) * ny, std::numeric_limits<std::uint32_t>::max());
  std::uint32_t hint = geometry::SeabedHeight::kNoHint;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = std::min(box.min().x() + i * cell, box.max().x());
      const double y = std::min(box.min().y() + j * cell, box.max().y());
      geometry::SeabedHeight::Sample sample;
      if (!height.sample(x, y, &sample, &hint)) continue;
      vertex[static_cast<std::size_t>(j) * nx + i] = static_cast<std::uint32_t>(positions.size() / 3);
      for (const double value : {x, y, sample.height}) positions.push_back(static_cast<float>(value));
    }
  }
  std::vector<std::uint32_t> indices;
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * nx + i;
      const std::uint32_t a = vertex[k], b = vertex[k + 1], c = vertex[k + nx + 1], d = vertex[k + nx];
      if (std::max({a, b, c, d}) == std::numeric_limits<std::uint32_t>::max()) continue;
      indices.insert(indices.end(), {a, b, c, a, c, d});
    }
  }
  out.positions(positions);
  out.indices(indices);
}

// How far a sensor's beams reach and its cone's half angle: its kind's reach().
sensors::SensorReach sensor_reach(const SensorSpec& sensor) {
  return std::visit([](const auto& spec) { return sensors::KindOf<std::decay_t<decltype(spec)>>::reach(spec); },
                    sensor.kind);
}

// The name a scene gives body k of an articulated vehicle: its joint link's, "base_link" for the base.
std::string body_name(const VehicleSpec& vehicle, const physics::Articulation& a, int body) {
  return body <= 0 ? std::string("base_link") : vehicle.links[static_cast<std::size_t>(a.body(body).joint_link)].name;
}

// An articulated vehicle's moving bodies: a mesh each (in its frame K, when it has geometry) and its
// SceneLink, parents first (Articulation's order).
void add_moving_bodies(const VehicleSpec& vehicle, const physics::Articulation& a, const Eigen::Array3d& albedo,
                       hadal_msgs::msg::Scene& msg) {
  for (int k = 1; k < a.num_bodies(); ++k) {
    const physics::Articulation::Body& body = a.body(k);
    const std::string name = body_name(vehicle, a, k);
    std::vector<std::pair<int, Eigen::Isometry3d>> X_KL;
    for (const int l : body.links) X_KL.emplace_back(l, a.X_KL(l));
    const geometry::TriangleMesh mesh_K = geometry::links_visual_A(vehicle, X_KL);
    if (mesh_K.num_triangles() > 0) {
      hadal_msgs::msg::SceneMesh& mesh = msg.meshes().emplace_back();
      mesh.name(vehicle.name + "/" + name);
      mesh.frame_id(vehicle.name + "/" + name);
      copy_mesh(mesh_K, mesh);
      set_color(albedo, mesh.color());
    }
    hadal_msgs::msg::SceneLink& link = msg.links().emplace_back();
    link.vehicle(vehicle.name);
    link.name(name);
    link.parent(body_name(vehicle, a, body.parent));
    link.joint(joint_name(vehicle.links[static_cast<std::size_t>(body.joint_link)]));
    link.joint_type(to_string(body.joint.type));
    set_pose(body.X_PK0, link.pose());
    link.axis().x(body.axis_K.x());
    link.axis().y(body.axis_K.y());
    link.axis().z(body.axis_K.z());
  }
}

Eigen::Array3d vehicle_albedo(const Model& model, const VehicleSpec& vehicle) {
  for (const LinkSpec& link : vehicle.links) {
    if (link.appearance.albedo) return *link.appearance.albedo;
  }
  return model.world.optics.vehicle_albedo;
}

}  // namespace

void fill_scene(const Model& model, double time_s, hadal_msgs::msg::Scene& msg) {
  msg.header().stamp(to_time_msg(time_s));
  msg.header().frame_id(model.world.frame_id);
  msg.scenario(std::filesystem::path(model.scenario_file).filename().string());
  msg.vehicle_names().clear();
  msg.vehicle_types().clear();
  msg.meshes().clear();
  msg.frames().clear();
  msg.links().clear();
  msg.wave_components().clear();
  msg.wave_ramp_time_s(0.0);
  if (model.world.waves.enabled()) {  // the simulation's own sea (physics::Ocean builds it from the world)
    const physics::Ocean ocean(model.world);
    for (const physics::WaveComponent& c : ocean.waves().components()) {
      hadal_msgs::msg::WaveComponent& out = msg.wave_components().emplace_back();
      out.amplitude_m(c.amplitude);
      out.omega_rad_per_s(c.omega);
      out.wave_number_rad_per_m(c.k);
      out.direction_rad(c.direction);
      out.phase_rad(c.phase);
    }
    msg.wave_ramp_time_s(ocean.waves().ramp_time());
  }

  const SeabedSpec& seabed = model.world.seabed;
  msg.seabed_is_plane(seabed.type == SeabedType::kPlane || !seabed.mesh);
  msg.seabed_plane_z(seabed.z);
  msg.water_surface_z(model.world.water.surface_z);
  hadal_msgs::msg::SceneMesh& ground = msg.meshes().emplace_back();
  ground.name("seabed");
  ground.frame_id(model.world.frame_id);
  set_color(model.world.optics.seabed_albedo, ground.color());
  if (msg.seabed_is_plane()) {
    plane_mesh(model, seabed.z, ground);
  } else if (seabed.mesh->num_triangles() <= kMaxSeabedTriangles) {
    copy_mesh(*seabed.mesh, ground);
  } else {
    resampled_mesh(*seabed.mesh, ground);
  }

  for (const VehicleSpec& vehicle : model.vehicles) {
    msg.vehicle_names().push_back(vehicle.name);
    msg.vehicle_types().push_back(to_string(vehicle.type));
    hadal_msgs::msg::SceneMesh& mesh = msg.meshes().emplace_back();
    mesh.name(vehicle.name);
    mesh.frame_id(vehicle.name + "/base_link");
    copy_mesh(geometry::vehicle_visual_B(vehicle), mesh);
    set_color(vehicle_albedo(model, vehicle), mesh.color());
    // An articulated vehicle's moving bodies, and the frames on them (which name the body and their pose in
    // it, so that a viewer moves them with it).
    std::optional<physics::Articulation> articulation;
    if (physics::is_articulated(vehicle.links)) {
      articulation.emplace(vehicle.links);
      add_moving_bodies(vehicle, *articulation, vehicle_albedo(model, vehicle), msg);
    }

    const auto on_body = [&](int link, const Eigen::Isometry3d& X_LF, hadal_msgs::msg::SceneFrame& frame) {
      if (!articulation || articulation->body_of_link(link) == 0) return;
      frame.link(body_name(vehicle, *articulation, articulation->body_of_link(link)));
      set_pose(articulation->X_KL(link) * X_LF, frame.link_pose());
    };
    for (const SensorSpec& sensor : vehicle.sensors) {
      // Every sensor, so that clients know them all; one on a moving link at its pose in B with every joint
      // at zero.
      hadal_msgs::msg::SceneFrame& frame = msg.frames().emplace_back();
      frame.vehicle(vehicle.name);
      frame.name(sensor.name);
      frame.kind(std::string(sensor.type()));
      frame.frame_id(sensor.frame_id);
      set_pose(vehicle.links[sensor.link_index].X_BL * sensor.X_LS, frame.pose());
      on_body(sensor.link_index, sensor.X_LS, frame);
      const sensors::SensorReach reach = sensor_reach(sensor);
      frame.range(reach.range_m);
      frame.half_angle(reach.half_angle_rad);
    }
    for (const LightSpec& light : vehicle.lights) {
      hadal_msgs::msg::SceneFrame& frame = msg.frames().emplace_back();
      frame.vehicle(vehicle.name);
      frame.name(light.name);
      frame.kind("light");
      frame.frame_id(vehicle.name + "/" + light.name);
      set_pose(vehicle.links[light.link_index].X_BL * light.X_LF, frame.pose());
      on_body(light.link_index, light.X_LF, frame);
      frame.range(kLightReach);
      frame.half_angle(light.outer_half_angle);
    }
  }
}

}  // namespace hadal::dds

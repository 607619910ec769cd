// Rays cast on the calling thread into a view of the world scene posed at a state: what the sensors
// sampled on the stepping thread use (DVL beams, altimeters), so their samples are as deterministic as
// the rest of the step. The bodies are moved to a state's poses on the first cast at each step count.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "hadal/core/state.h"
#include "hadal/geometry/embree_scene.h"
#include "hadal/geometry/ray_batch.h"

namespace hadal::geometry {

class SceneRays {
 public:
  // The ray bodies' poses at a state (geometry/world_scene.h): Simulation::ray_body_poses.
  using Poses = std::function<std::vector<Eigen::Isometry3d>(const SimState&)>;

  // A view of the world (EmbreeScene::view()); built here if it is not yet. Without `poses` the bodies are
  // the vehicles' base bodies at their X_WB (a world without moving bodies).
  explicit SceneRays(EmbreeScene scene, Poses poses = {}) : scene_(std::move(scene)), poses_of_(std::move(poses)) {
    if (!scene_.built()) scene_.build();
  }

  // Distances [m] along the unit directions d_W from p_W in the world at `state`, passing through ray body
  // `own` (the body a sensor is mounted on); +inf where nothing is hit within max_distance.
  template <std::size_t N>
  std::array<double, N> cast(const SimState& state, const Eigen::Vector3d& p_W,
                             const std::array<Eigen::Vector3d, N>& d_W, int own, double max_distance) {
    pose(state);
    rays_.clear_rays();
    for (const Eigen::Vector3d& d : d_W) {
      rays_.add_ray(p_W.cast<float>(), d.normalized().cast<float>(), 0.0f, static_cast<float>(max_distance),
                    static_cast<std::int32_t>(own));
    }
    hits_.resize(N);
    scene_.intersect(rays_, 0, N, QueryPath::kSingle, hits_);
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = hits_.distance[i];
    return out;
  }

  // The next cast re-poses the bodies even at the same step count (after a state was restored).
  void invalidate() { posed_step_.reset(); }

  const EmbreeScene& scene() const { return scene_; }

 private:
  void pose(const SimState& state) {
    if (posed_step_ == state.step_count) return;
    if (poses_of_) {
      poses_ = poses_of_(state);
    } else {
      poses_.clear();
      for (const VehicleState& vehicle : state.vehicles) poses_.push_back(vehicle.body.X_WB);
    }
    scene_.set_body_poses(poses_);
    posed_step_ = state.step_count;
  }

  EmbreeScene scene_;
  Poses poses_of_;
  RayBatch rays_;
  RayHits hits_;
  std::vector<Eigen::Isometry3d> poses_;
  std::optional<std::uint64_t> posed_step_;  // the step whose poses the scene holds; none: stale
};

}  // namespace hadal::geometry

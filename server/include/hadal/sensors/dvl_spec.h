// The DVL's spec (sensors/dvl_sensor.h, sensors/dvl.h; keys: DvlSensor::keys()).
#pragma once

#include <Eigen/Core>

#include <cstdint>

#include "hadal/core/units.h"
#include "hadal/sensors/noise_params.h"

namespace hadal::sensors {

struct DvlSensor;

enum class DvlType : std::uint8_t { kPiston = 0, kPhasedArray = 1 };

// The paper's slowly varying velocity bias (header text), S axes.
struct DvlBiasParams {
  Eigen::Vector3d initial = Eigen::Vector3d::Zero();     // b_0 [m/s]
  double initial_sigma = 0.0;                            // sigma_b0, drawn per axis per run [m/s]
  Eigen::Vector3d drift_rate = Eigen::Vector3d::Zero();  // xi_fixed [m/s^2]
  double drift_rate_sigma = 0.0;                         // sigma_xi, drawn per axis per run [m/s^2]
  double random_walk_density = 0.0;                      // K [m/s/sqrt(s)] = [m s^-3/2]
};

struct DvlParams {
  DvlType type = DvlType::kPiston;                 // reported only
  double beam_tilt = 30.0 * kPi / 180.0;           // theta [rad], in (0, pi/2)
  double first_beam_azimuth = 45.0 * kPi / 180.0;  // phi_1 [rad]
  double min_altitude = 0.7;                       // bottom-lock window along the axis [m]
  double max_altitude = 90.0;
  double dropout_probability = 0.0;     // p per beam per ping, [0, 1]
  double assumed_sound_speed = 0.0;     // c_assumed [m/s]; 0 = the true one (k = 1)
  bool water_track = true;              // water-track mode without bottom lock
  double water_track_layer_near = 2.0;  // layer along the axis [m], near < far
  double water_track_layer_far = 6.0;
  // Per-beam channels (noise.h). Their white noise is a density N: a ping's std is N / sqrt(dt), so a
  // per-ping sigma at sample period T is N = sigma sqrt(T) (what dvl_params does).
  NoiseChannelParams beam_velocity_noise;         // eta_i, bottom track [m/s]
  NoiseChannelParams water_track_velocity_noise;  // eta_i, water track [m/s]
  NoiseChannelParams range_noise;                 // slant-range error [m]
  DvlBiasParams bias;
};

struct DvlSpec {
  using Kind = DvlSensor;
  DvlParams params;
  int water_track_layer_samples = 4;  // current samples per beam across the water-track layer
};

}  // namespace hadal::sensors

// The IMU's spec (sensors/imu_sensor.h; keys: ImuSensor::keys()): its data sheet's figures and the noise triads made of them.
#pragma once

#include <limits>

#include "hadal/sensors/noise_params.h"

namespace hadal::sensors {

struct ImuSensor;

// Figures as the data sheet gives them (0 = not listed); a preset's figures (config/preset.h). The
// accelerometer bias figure is used as its bias instability.
struct ImuDatasheet {
  double gyro_arw_deg_per_sqrt_h = 0.0;
  double gyro_bias_instability_deg_per_h = 0.0;
  double gyro_rrw_deg_per_h_per_sqrt_h = 0.0;
  double gyro_scale_factor_ppm = 0.0;        // 1-sigma, drawn per run
  double gyro_misalignment_rad = 0.0;        // 1-sigma, drawn per run
  double accel_noise_density = 0.0;          // [m/s^2/sqrt(Hz)], from VRW or ug/sqrt(Hz)
  double accel_bias_instability_mps2 = 0.0;  // [m/s^2]
  double accel_scale_factor_ppm = 0.0;       // 1-sigma, drawn per run
  double accel_range_mps2 = std::numeric_limits<double>::infinity();
};

// The figures as the file gives them, in data-sheet units (a preset's, overridden key by key); the
// triads below are made of them when the keys are read.
struct ImuFigures {
  ImuDatasheet sheet;
  double gyro_range_deg_per_s = 0.0;       // 0: unlimited
  double gyro_resolution_deg_per_s = 0.0;  // 0: none
  double accel_range_g = 0.0;              // 0: unlimited
  double accel_resolution_mg = 0.0;        // 0: none
  double accel_misalignment_deg = 0.0;     // 1-sigma, drawn per run
  bool white_noise_only = false;           // keep only the white noise
};
struct ImuSpec {
  using Kind = ImuSensor;
  ImuFigures figures;
  NoiseTriadParams gyro;   // [rad/s]
  NoiseTriadParams accel;  // [m/s^2]
  double temperature_reference = 20.0;         // T_ref [degC]
  double gyro_temperature_coefficient = 0.0;   // k_T [rad/s per K], every axis
  double accel_temperature_coefficient = 0.0;  // k_T [m/s^2 per K], every axis
  int vibration_thruster = -1;                 // index of a thruster in the vehicle's actuators; -1: none
  int vibration_blades = 3;                    // blade-pass frequency = blades x rotor speed
  double gyro_vibration_amplitude = 0.0;       // A [rad/s], every axis
  double accel_vibration_amplitude = 0.0;      // A [m/s^2], every axis
};

}  // namespace hadal::sensors

// The magnetometer's spec (sensors/magnetometer_sensor.h, sensors/magnetometer.h; keys: MagnetometerSensor::keys()).
#pragma once

#include <Eigen/Core>

#include <vector>

#include "hadal/sensors/magnetic_dipole.h"
#include "hadal/sensors/noise_params.h"

namespace hadal::sensors {

struct MagnetometerSensor;

struct MagnetometerParams {
  std::vector<MagneticDipole> dipoles_B;  // hard iron fixed in the vehicle: p_BD [m], m_B [A m^2]
  std::vector<MagneticDipole> dipoles_W;  // static dipoles in the world: p_WD [m], m_W [A m^2]
  Eigen::Matrix3d soft_iron_S = Eigen::Matrix3d::Identity();  // S_S, in sensor axes [-]
  NoiseTriadParams noise;                                     // [T]
};

struct MagnetometerSpec {
  using Kind = MagnetometerSensor;
  // Hard iron (dipoles_B), soft iron and noise. params.dipoles_W stays empty: the world's dipoles
  // are the world's (WorldSpec::magnetic_dipoles_W) and enter with the Earth's field.
  MagnetometerParams params;
};

}  // namespace hadal::sensors

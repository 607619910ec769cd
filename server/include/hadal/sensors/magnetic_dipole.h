// A magnetic dipole D fixed in a frame F (F = W for a wreck or pipeline: YAML world.magnetic_dipoles; F =
// B for a vehicle's hard iron: a magnetometer's hard_iron). sensors/magnetometer.h computes its field.
// Its keys are declared once in sensors::dipole_keys() (server/src/sensors/magnetic_dipole.cc).
#pragma once

#include <Eigen/Core>

#include "hadal/config/key_table_fwd.h"

namespace hadal::sensors {

struct MagneticDipole {
  Eigen::Vector3d p_FD = Eigen::Vector3d::Zero();  // position of D in F [m]
  Eigen::Vector3d m_F = Eigen::Vector3d::Zero();   // moment expressed in F [A m^2]
  double radius = 0.0;  // 0: point dipole; > 0: uniformly magnetised sphere (uniform field inside)
};

// {position [m], moment [A m^2], radius [m]}, in the frame of the list that holds it.
const config::KeyTable<MagneticDipole>& dipole_keys();

}  // namespace hadal::sensors

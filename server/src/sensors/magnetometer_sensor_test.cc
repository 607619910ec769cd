// The magnetometer kind alone (no Bullet): WMM2025 at the sensor's geodetic position, hard iron in the
// vehicle, the world's dipoles, its frame and its message.
#include "hadal/sensors/magnetometer_sensor.h"

#include <gtest/gtest.h>
#include <sensor_msgs.h>

#include <cmath>
#include <string>

#include "hadal/sensors/geomagnetic.h"
#include "sensor_test_support.h"

namespace hadal::sensors {
namespace {

using testing::pose;
using testing::rpy;
using testing::SensorTestWorld;

// A vehicle 30 m below W's origin at 43 N 5 E on 2026-06-01 (the tests sample at sim time 0.1 s).
Model model_at_43n() {
  Model model = testing::one_vehicle_world(Eigen::Vector3d(0, 0, -30.0));
  model.world.origin.latitude_rad = 43.0 * kDegToRad;
  model.world.origin.longitude_rad = 5.0 * kDegToRad;
  model.world.start_decimal_year = decimal_year_from_date(2026, 6, 1);
  return model;
}

GeomagneticModel wmm() {
  return GeomagneticModel::load_cof(std::string(HADAL_SOURCE_DIR) + "/server/data/WMM2025.COF");
}

// Without noise, on a vehicle aligned with W, the sensor reads WMM2025 at its geodetic position (height
// -30 m on the origin's normal) in ENU = S axes, to 1e-12 T (the synthesis is exact to rounding); a
// hard-iron dipole m = 1 A m^2 along z, 0.5 m ahead of the sensor, adds its equatorial closed form
// -mu0 m / (4 pi r^3) = -0.8 uT along z.
TEST(MagnetometerSensorTest, ReadsWmmPlusHardIron) {
  SensorTestWorld world(model_at_43n());
  world.state.time = 0.1;
  MagnetometerSensor::Spec plain;
  MagnetometerSensor::State state = world.initial_state<MagnetometerSensor>(plain, 10.0);
  world.sample<MagnetometerSensor>(plain, state, Eigen::Isometry3d::Identity(), 10.0);
  const double year = world.model.world.start_decimal_year + 0.1 / (365.25 * 86400.0);
  const Eigen::Vector3d expected =
      wmm().field(world.model.world.origin.latitude_rad, world.model.world.origin.longitude_rad, -30.0, year).B_ENU_T();
  EXPECT_NEAR((state.B_S - expected).norm(), 0.0, 1e-12);

  MagnetometerSensor::Spec iron;
  iron.params.dipoles_B = {{Eigen::Vector3d(0.5, 0.0, 0.0), Eigen::Vector3d(0.0, 0.0, 1.0), 0.0}};
  MagnetometerSensor::State with_iron = world.initial_state<MagnetometerSensor>(iron, 10.0);
  world.sample<MagnetometerSensor>(iron, with_iron, Eigen::Isometry3d::Identity(), 10.0);
  EXPECT_NEAR(with_iron.B_S.z() - state.B_S.z(), -1e-7 / 0.125, 1e-15);
  EXPECT_NEAR(with_iron.B_S.x() - state.B_S.x(), 0.0, 1e-15);
}

// A wreck in the world (world.magnetic_dipoles): its field at the sensor is fixed in W, 10 m south of it
// in its equatorial plane -mu0 m / (4 pi r^3) along its moment, and reaches a yawed sensor as R_SW B_W.
TEST(MagnetometerSensorTest, WorldDipolesAddToTheEarthField) {
  SensorTestWorld world(model_at_43n());
  world.state.time = 0.1;
  const MagnetometerSensor::Spec spec;
  const Eigen::Vector3d p_WS(0.0, 0.0, -30.0);
  MagnetometerSensor::State earth = world.initial_state<MagnetometerSensor>(spec, 10.0);
  const Eigen::Isometry3d X_BS = pose(Eigen::Vector3d::Zero(), rpy(0, 0, 0.6));
  world.sample<MagnetometerSensor>(spec, earth, X_BS, 10.0);
  world.model.world.magnetic_dipoles_W = {{p_WS + Eigen::Vector3d(0, 10.0, 0), Eigen::Vector3d(0, 0, 1e5), 3.0}};
  MagnetometerSensor::State wreck = world.initial_state<MagnetometerSensor>(spec, 10.0);
  world.sample<MagnetometerSensor>(spec, wreck, X_BS, 10.0);
  const double expected_z = -kVacuumPermeability * 1e5 / (4.0 * kPi * 1000.0);
  const Eigen::Vector3d difference_W = X_BS.linear() * (wreck.B_S - earth.B_S);
  EXPECT_NEAR((difference_W - Eigen::Vector3d(0, 0, expected_z)).norm(), 0.0, 1e-6 * std::abs(expected_z));
}

// sensor_msgs/MagneticField: the field in S, covariance N^2 rate_hz + lsb^2 / 12 on the diagonal.
TEST(MagnetometerSensorTest, Message) {
  MagnetometerSensor::Spec spec;
  for (auto& axis : spec.params.noise.axes) axis.white_noise_density = 2e-9;
  spec.params.noise.lsb = 1e-9;
  MagnetometerSensor::State state;
  state.B_S = Eigen::Vector3d(2e-5, 1e-6, -4e-5);
  sensor_msgs::msg::MagneticField msg;
  const std::string frame = "auv/mag";
  MagnetometerSensor::fill_message(spec, state, MessageHeader{2.0, frame, 20.0}, msg);
  EXPECT_EQ(msg.magnetic_field().z(), -4e-5);
  EXPECT_EQ(msg.magnetic_field_covariance()[8], 4e-18 * 20.0 + 1e-18 / 12.0);
  EXPECT_EQ(msg.magnetic_field_covariance()[1], 0.0);
  EXPECT_EQ(msg.header().frame_id(), "auv/mag");
}

}  // namespace
}  // namespace hadal::sensors

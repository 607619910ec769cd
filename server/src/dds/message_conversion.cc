#include "message_conversion.h"

#include <limits>

#include "hadal/dds/topic_names.h"


namespace hadal::dds {

void fill_odometry(const std::string& world_frame_id, const std::string& vehicle_name, double time_s,
                   const RigidBodyState& body, nav_msgs::msg::Odometry& msg) {
  msg.header().stamp(to_time_msg(time_s));
  msg.header().frame_id(world_frame_id);
  msg.child_frame_id(base_frame_id(vehicle_name));

  const Eigen::Vector3d& p_WB = body.X_WB.translation();
  const Eigen::Matrix3d R_WB = body.X_WB.rotation();
  const Eigen::Quaterniond q_WB(R_WB);
  auto& pose = msg.pose().pose();
  pose.position().x(p_WB.x());
  pose.position().y(p_WB.y());
  pose.position().z(p_WB.z());
  pose.orientation().x(q_WB.x());
  pose.orientation().y(q_WB.y());
  pose.orientation().z(q_WB.z());
  pose.orientation().w(q_WB.w());

  const Eigen::Vector3d v_WB_B = R_WB.transpose() * body.v_WB;
  const Eigen::Vector3d w_WB_B = R_WB.transpose() * body.w_WB;
  auto& twist = msg.twist().twist();
  twist.linear().x(v_WB_B.x());
  twist.linear().y(v_WB_B.y());
  twist.linear().z(v_WB_B.z());
  twist.angular().x(w_WB_B.x());
  twist.angular().y(w_WB_B.y());
  twist.angular().z(w_WB_B.z());
}

void fill_thruster_state(const VehicleSpec& spec, const VehicleState& state, double time_s,
                         hadal_msgs::msg::ThrusterState& msg) {
  msg.header().stamp(to_time_msg(time_s));
  msg.header().frame_id(base_frame_id(spec.name));
  const std::size_t n = spec.thrusters.size();
  msg.name().resize(n);
  msg.setpoint().resize(n);
  msg.rotor_speed().resize(n);
  msg.thrust().resize(n);
  msg.torque().resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    msg.name()[i] = spec.thrusters[i].name;
    msg.setpoint()[i] = state.thrusters[i].setpoint;
    msg.rotor_speed()[i] = state.thrusters[i].rotor_speed;
    msg.thrust()[i] = state.thrusters[i].thrust;
    msg.torque()[i] = state.thrusters[i].torque;
  }
  msg.command_source(static_cast<std::uint8_t>(state.command_source));
}

void fill_fluid_pressure(const SensorSpec& spec, const SensorState& sample,
                         sensor_msgs::msg::FluidPressure& msg) {
  msg.header().stamp(to_time_msg(sample.stamp));
  msg.header().frame_id(spec.frame_id);
  msg.fluid_pressure(sample.value.empty() ? 0.0 : sample.value[0]);
  const PressureSensorSpec& p = spec.pressure;
  msg.variance(p.noise_stddev * p.noise_stddev + p.resolution * p.resolution / 12.0);
}

void fill_imu(const SensorSpec& spec, const SensorState& sample, sensor_msgs::msg::Imu& msg) {
  msg.header().stamp(to_time_msg(sample.stamp));
  msg.header().frame_id(spec.frame_id);
  msg.orientation().x(0.0);
  msg.orientation().y(0.0);
  msg.orientation().z(0.0);
  msg.orientation().w(1.0);
  msg.orientation_covariance().fill(0.0);
  msg.orientation_covariance()[0] = -1.0;
  double value[6] = {0, 0, 0, 0, 0, 0};
  for (std::size_t c = 0; c < 6 && c < sample.value.size(); ++c) value[c] = sample.value[c];
  msg.angular_velocity().x(value[0]);
  msg.angular_velocity().y(value[1]);
  msg.angular_velocity().z(value[2]);
  msg.linear_acceleration().x(value[3]);
  msg.linear_acceleration().y(value[4]);
  msg.linear_acceleration().z(value[5]);
  const double rate = spec.rate_hz;
  msg.angular_velocity_covariance().fill(0.0);
  msg.linear_acceleration_covariance().fill(0.0);
  for (int a = 0; a < 3; ++a) {
    const double n_gyro = spec.imu.gyro.axes[a].white_noise_density;
    const double n_accel = spec.imu.accel.axes[a].white_noise_density;
    msg.angular_velocity_covariance()[4 * a] = n_gyro * n_gyro * rate;
    msg.linear_acceleration_covariance()[4 * a] = n_accel * n_accel * rate;
  }
}

void fill_magnetic_field(const SensorSpec& spec, const SensorState& sample, sensor_msgs::msg::MagneticField& msg) {
  msg.header().stamp(to_time_msg(sample.stamp));
  msg.header().frame_id(spec.frame_id);
  double value[3] = {0, 0, 0};
  for (std::size_t c = 0; c < 3 && c < sample.value.size(); ++c) value[c] = sample.value[c];
  msg.magnetic_field().x(value[0]);
  msg.magnetic_field().y(value[1]);
  msg.magnetic_field().z(value[2]);
  msg.magnetic_field_covariance().fill(0.0);
  const sensors::NoiseTriadParams& noise = spec.magnetometer.params.noise;
  for (int a = 0; a < 3; ++a) {
    const double n = noise.axes[a].white_noise_density;
    msg.magnetic_field_covariance()[4 * a] = n * n * spec.rate_hz + noise.lsb * noise.lsb / 12.0;
  }
}

void fill_nav_sat_fix(const SensorSpec& spec, const SensorState& sample, sensor_msgs::msg::NavSatFix& msg) {
  msg.header().stamp(to_time_msg(sample.stamp));
  msg.header().frame_id(spec.frame_id);
  const bool fix = sample.value.size() == 4 && sample.value[3] > 0.5;
  msg.status().status(fix ? sensor_msgs::msg::NavSatStatus_Constants::STATUS_FIX
                          : sensor_msgs::msg::NavSatStatus_Constants::STATUS_NO_FIX);
  msg.status().service(sensor_msgs::msg::NavSatStatus_Constants::SERVICE_GPS);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  msg.latitude(fix ? sample.value[0] : nan);
  msg.longitude(fix ? sample.value[1] : nan);
  msg.altitude(fix ? sample.value[2] : nan);
  const double h2 = spec.gps.horizontal_stddev * spec.gps.horizontal_stddev;
  const double v2 = spec.gps.vertical_stddev * spec.gps.vertical_stddev;
  msg.position_covariance({h2, 0, 0, 0, h2, 0, 0, 0, v2});
  msg.position_covariance_type(sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_DIAGONAL_KNOWN);
}

void fill_dvl(const SensorSpec& spec, const SensorState& sample, marine_acoustic_msgs::msg::Dvl& msg) {
  namespace C = marine_acoustic_msgs::msg::Dvl_Constants;
  msg.header().stamp(to_time_msg(sample.stamp));
  msg.header().frame_id(spec.frame_id);
  const sensors::DvlPing ping = sample.dvl_ping.value_or(sensors::DvlPing{});
  switch (ping.mode) {
    case sensors::DvlMode::kNone: msg.velocity_mode(0); break;
    case sensors::DvlMode::kBottomTrack: msg.velocity_mode(C::DVL_MODE_BOTTOM); break;
    case sensors::DvlMode::kWaterTrack: msg.velocity_mode(C::DVL_MODE_WATER); break;
  }
  msg.dvl_type(ping.type == sensors::DvlType::kPhasedArray ? C::DVL_TYPE_PHASED_ARRAY : C::DVL_TYPE_PISTON);
  msg.velocity().x(ping.velocity.x());
  msg.velocity().y(ping.velocity.y());
  msg.velocity().z(ping.velocity.z());
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      msg.velocity_covar()[static_cast<std::size_t>(3 * r + c)] = ping.velocity_covariance(r, c);
    }
  }
  msg.altitude(ping.altitude);
  msg.course_gnd(ping.course_gnd);
  msg.speed_gnd(ping.speed_gnd);
  msg.num_good_beams(static_cast<std::uint8_t>(ping.num_good_beams));
  msg.sound_speed(static_cast<float>(ping.sound_speed));
  msg.beam_ranges_valid(ping.beam_ranges_valid);
  msg.beam_velocities_valid(ping.beam_velocities_valid);
  for (std::size_t b = 0; b < static_cast<std::size_t>(sensors::kDvlBeams); ++b) {
    msg.beam_unit_vec()[b].x(ping.beam_unit_vec[b].x());
    msg.beam_unit_vec()[b].y(ping.beam_unit_vec[b].y());
    msg.beam_unit_vec()[b].z(ping.beam_unit_vec[b].z());
    msg.range()[b] = ping.range[b];
    msg.range_covar()[b] = static_cast<float>(ping.range_covar[b]);
    msg.beam_quality()[b] = static_cast<float>(ping.beam_quality[b]);
    msg.beam_velocity()[b] = static_cast<float>(ping.beam_velocity[b]);
    msg.beam_velocity_covar()[b] = static_cast<float>(ping.beam_velocity_covar[b]);
  }
}

void fill_range(const SensorSpec& spec, const SensorState& sample, sensor_msgs::msg::Range& msg) {
  msg.header().stamp(to_time_msg(sample.stamp));
  msg.header().frame_id(spec.frame_id);
  msg.radiation_type(sensor_msgs::msg::Range_Constants::ULTRASOUND);
  msg.field_of_view(static_cast<float>(spec.altimeter.field_of_view));
  msg.min_range(static_cast<float>(spec.altimeter.min_range));
  msg.max_range(static_cast<float>(spec.altimeter.max_range));
  msg.range(sample.value.empty() ? std::numeric_limits<float>::infinity() : static_cast<float>(sample.value[0]));
}

}  // namespace hadal::dds

// Conversions between Hadal's state and the ROS 2 message types on the wire.
//
// Odometry follows nav_msgs/Odometry's convention: pose of the body frame B in the world frame
// (header.frame_id, ENU), twist expressed in the child frame B (v_WB_B, w_WB_B). Covariances are zero:
// this is ground truth. Sensor messages carry the sensor's last sample (noise applied in the simulation).
#pragma once

#include "hadal/core/model.h"
#include "hadal/core/state.h"

#include "hadal/dds/time_msg.h"

#include <hadal_msgs.h>
#include <marine_acoustic_msgs.h>
#include <nav_msgs.h>
#include <sensor_msgs.h>

namespace hadal::dds {

void fill_odometry(const std::string& world_frame_id, const std::string& vehicle_name, double time_s,
                   const RigidBodyState& body, nav_msgs::msg::Odometry& msg);

void fill_thruster_state(const VehicleSpec& spec, const VehicleState& state, double time_s,
                         hadal_msgs::msg::ThrusterState& msg);

// A pressure sensor's last sample: absolute pressure [Pa] and its variance (noise_stddev^2 plus the
// quantisation's resolution^2 / 12), stamped with the sample's sim time.
void fill_fluid_pressure(const SensorSpec& spec, const SensorState& sample,
                         sensor_msgs::msg::FluidPressure& msg);

// An IMU's last sample: angular velocity and linear acceleration (specific force) in the sensor frame,
// diagonal covariances from the white noise (N^2 / T per axis, T the sample period), no orientation
// (orientation_covariance[0] = -1, the ROS convention for "not provided").
void fill_imu(const SensorSpec& spec, const SensorState& sample, sensor_msgs::msg::Imu& msg);

// A magnetometer's last sample [T] in the sensor frame; covariance diagonal from its white noise.
void fill_magnetic_field(const SensorSpec& spec, const SensorState& sample, sensor_msgs::msg::MagneticField& msg);

// A GPS fix: STATUS_FIX with latitude/longitude [deg] and height above the ellipsoid [m] while the
// antenna is above water, STATUS_NO_FIX with NaN position otherwise; diagonal ENU covariance.
void fill_nav_sat_fix(const SensorSpec& spec, const SensorState& sample, sensor_msgs::msg::NavSatFix& msg);

// A DVL's last ping (sensors/dvl.h's DvlPing) as marine_acoustic_msgs/Dvl, in the sensor frame:
// velocity_mode 0 (none) / DVL_MODE_BOTTOM / DVL_MODE_WATER, velocity and its covariance (NaN and -1
// without a solution), altitude, course and speed over ground, beams' unit vectors, ranges (NaN: no
// return) and velocities (NaN: not in the solution) with their variances (-1: none), beam_quality 1/0.
void fill_dvl(const SensorSpec& spec, const SensorState& sample, marine_acoustic_msgs::msg::Dvl& msg);

// An altimeter's last sample as sensor_msgs/Range (ULTRASOUND): range [m] within [min_range,
// max_range], -inf when the seabed is closer than min_range, +inf when nothing is within max_range
// (REP 117).
void fill_range(const SensorSpec& spec, const SensorState& sample, sensor_msgs::msg::Range& msg);

}  // namespace hadal::dds

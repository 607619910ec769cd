#include "hadal/sensors/force_torque_sensor.h"

#include <geometry_msgs.h>
#include <geometry_msgsPubSubTypes.h>

#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/dds/time_msg.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::Range;

namespace {

NoiseTriadParams triad(double stddev, double offset_stddev, double lsb, double range, double period) {
  NoiseTriadParams params;
  for (AxisNoiseParams& axis : params.axes) {
    axis.white_noise_density = stddev * std::sqrt(period);
    axis.turn_on_bias_sigma = offset_stddev;
  }
  params.lsb = lsb;
  params.min = -range;
  params.max = range;
  return params;
}

}  // namespace

NoiseTriadParams ForceTorqueSensor::force_channel(const Spec& spec, double period) {
  return triad(spec.force_noise_stddev, spec.force_offset_stddev, spec.force_resolution, spec.force_range_n, period);
}

NoiseTriadParams ForceTorqueSensor::torque_channel(const Spec& spec, double period) {
  return triad(spec.torque_noise_stddev, spec.torque_offset_stddev, spec.torque_resolution, spec.torque_range_nm,
               period);
}

void ForceTorqueSensor::ideal(const Spec& spec, const Eigen::Isometry3d& X_LS,
                              const Eigen::Matrix<double, 6, 1>& wrench_L, Eigen::Vector3d& force_S,
                              Eigen::Vector3d& torque_S) {
  const Eigen::Matrix3d R_SL = X_LS.linear().transpose();
  const Eigen::Vector3d F_L = wrench_L.head<3>();
  const Eigen::Vector3d N_L = wrench_L.tail<3>() - X_LS.translation().cross(F_L);
  const double sign = spec.parent_to_child ? 1.0 : -1.0;
  force_S = sign * (R_SL * F_L);
  torque_S = sign * (R_SL * N_L);
}

SensorReach ForceTorqueSensor::reach(const Spec& /*spec*/) { return {}; }

const config::KeyTable<ForceTorqueSensor::Spec, SensorReader>& ForceTorqueSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].force_torque",
               "the wrench across the joint of its link (a link on a moving joint), in the sensor's frame about "
               "its origin");
    t.choice("measure_direction", &Spec::parent_to_child,
             {{"child_to_parent", false, "what the link and its load put on the parent (a load reads along gravity)"},
              {"parent_to_child", true, "what the parent puts on the link"}})
        .doc("which side's wrench (Gazebo's measure_direction)");
    t.number("force_noise_stddev", &Spec::force_noise_stddev).unit("N").range(Range::non_negative())
        .doc("white noise per sample, each axis");
    t.number("torque_noise_stddev", &Spec::torque_noise_stddev).unit("N m").range(Range::non_negative())
        .doc("white noise per sample, each axis");
    t.number("force_offset_stddev", &Spec::force_offset_stddev).unit("N").range(Range::non_negative())
        .doc("1-sigma of a zero offset drawn per run (seeded), each axis");
    t.number("torque_offset_stddev", &Spec::torque_offset_stddev).unit("N m").range(Range::non_negative())
        .doc("1-sigma of a zero offset drawn per run (seeded), each axis");
    t.number("force_resolution", &Spec::force_resolution).unit("N").range(Range::non_negative())
        .doc("quantisation step; 0: none");
    t.number("torque_resolution", &Spec::torque_resolution).unit("N m").range(Range::non_negative())
        .doc("quantisation step; 0: none");
    t.number("force_range_n", &Spec::force_range_n).unit("N").range(Range::positive()).default_text("unlimited")
        .doc("full scale: each axis clips to +-force_range_n");
    t.number("torque_range_nm", &Spec::torque_range_nm).unit("N m").range(Range::positive())
        .default_text("unlimited").doc("full scale: each axis clips to +-torque_range_nm");
  });
}

ForceTorqueSensor::State ForceTorqueSensor::initial_state(const Spec& spec, const SensorSetup& setup) {
  State state;
  state.force_noise = make_noise_state(force_channel(spec, setup.period),
                                       channel_key(setup.seed, setup.vehicle, setup.sensor, "force"));
  state.torque_noise = make_noise_state(torque_channel(spec, setup.period),
                                        channel_key(setup.seed, setup.vehicle, setup.sensor, "torque"));
  return state;
}

void ForceTorqueSensor::sample(const SampleContext& context, const Spec& spec, State& state) {
  const VehicleState& vehicle = context.vehicle();
  const auto link = static_cast<std::size_t>(context.sensor->link_index);
  Eigen::Vector3d force_S = Eigen::Vector3d::Zero(), torque_S = Eigen::Vector3d::Zero();
  if (link < vehicle.joint_wrenches_L.size()) {
    ideal(spec, context.sensor->X_LS, vehicle.joint_wrenches_L[link], force_S, torque_S);
  }
  state.force_S = measure(force_channel(spec, context.period), state.force_noise, force_S, context.period);
  state.torque_S = measure(torque_channel(spec, context.period), state.torque_noise, torque_S, context.period);
}

void ForceTorqueSensor::fill_message(const Spec& /*spec*/, const State& state, const MessageHeader& header,
                                     Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.wrench().force().x(state.force_S.x());
  msg.wrench().force().y(state.force_S.y());
  msg.wrench().force().z(state.force_S.z());
  msg.wrench().torque().x(state.torque_S.x());
  msg.wrench().torque().y(state.torque_S.y());
  msg.wrench().torque().z(state.torque_S.z());
}

}  // namespace hadal::sensors

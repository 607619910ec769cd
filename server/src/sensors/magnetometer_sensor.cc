#include "hadal/sensors/magnetometer_sensor.h"

#include <sensor_msgs.h>
#include <sensor_msgsPubSubTypes.h>

#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/dds/time_msg.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::Range;

SensorReach MagnetometerSensor::reach(const Spec& /*spec*/) { return {}; }

const config::KeyTable<MagnetometerSensor::Spec, SensorReader>& MagnetometerSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].magnetometer",
               "WMM2025 at the sensor, the world's and the vehicle's dipoles, soft iron, noise");
    t.number_into(
         "noise_stddev_nt",
         [](Spec& spec, double nt, SensorReader& reader) {
           for (auto& axis : spec.params.noise.axes) axis.white_noise_density = nt * 1e-9 / std::sqrt(reader.rate_hz);
         },
         [](Spec&) { return 0.0; })
        .unit("nT").range(Range::non_negative()).doc("white noise per sample");
    t.number("resolution_nt", [](Spec& spec) -> double& { return spec.params.noise.lsb; })
        .convert([](double nt) { return nt * 1e-9; }, [](double t) { return t / 1e-9; }, "nT")
        .range(Range::non_negative()).doc("quantisation step; 0: none");
    t.number_into(
         "range_ut", [](Spec& spec, double ut, SensorReader&) { spec.params.noise.min = -(spec.params.noise.max = ut * 1e-6); },
         nullptr)
        .unit("µT").range(Range::positive()).doc("readings clip to +-range");
    t.list("hard_iron", [](Spec& spec) -> std::vector<MagneticDipole>& { return spec.params.dipoles_B; }, dipole_keys())
        .drop_invalid()
        .doc("the vehicle's hard-iron dipoles, in B");
    t.numbers(
         "soft_iron", 9,
         [](Spec& spec, const std::vector<double>& v) {
           spec.params.soft_iron_S = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(v.data());
         },
         [](Spec&) { return std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1}; })
        .doc("row-major 3x3 S in sensor axes: B = S (B_earth + B_dipoles)");
  });
}

MagnetometerSensor::State MagnetometerSensor::initial_state(const Spec& spec, const SensorSetup& setup) {
  setup.environment.geomagnetic();  // load the model now: a missing file is a start-up error
  State state;
  state.noise = make_magnetometer_state(spec.params,
                                        channel_key(setup.seed, setup.vehicle, setup.sensor, "magnetic_field"));
  return state;
}

void MagnetometerSensor::sample(const SampleContext& context, const Spec& spec, State& state) {
  const double year = context.world.start_decimal_year + context.time / (365.25 * 86400.0);
  const Eigen::Vector3d p_WS = context.p_WS();
  const Eigen::Vector3d B_W =
      earth_field_W_T(context.environment.geomagnetic(), context.environment.frame_W(), p_WS, year) +
      dipoles_field_T(context.world.magnetic_dipoles_W, p_WS);
  state.B_S = measure_magnetic_field(spec.params, state.noise, B_W, context.body().X_WB, context.X_BS,
                                     context.period)
                  .B_measured_S;
}

void MagnetometerSensor::fill_message(const Spec& spec, const State& state, const MessageHeader& header,
                                      Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.magnetic_field().x(state.B_S.x());
  msg.magnetic_field().y(state.B_S.y());
  msg.magnetic_field().z(state.B_S.z());
  msg.magnetic_field_covariance().fill(0.0);
  const NoiseTriadParams& noise = spec.params.noise;
  for (int a = 0; a < 3; ++a) {
    const double n = noise.axes[a].white_noise_density;
    msg.magnetic_field_covariance()[4 * a] = n * n * header.rate_hz + noise.lsb * noise.lsb / 12.0;
  }
}

}  // namespace hadal::sensors

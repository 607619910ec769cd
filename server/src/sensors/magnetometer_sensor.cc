#include "hadal/sensors/magnetometer_sensor.h"

#include <sensor_msgs.h>
#include <sensor_msgsPubSubTypes.h>

#include <cmath>

#include "hadal/config/yaml_reader.h"
#include "hadal/dds/time_msg.h"
#include "hadal/sensors/sample_context.h"

namespace hadal::sensors {

using config::MapReader;
using config::Need;
using config::Range;
using config::Value;

namespace {

// A magnetic dipole {position [m], moment [A m^2], radius [m] (0: point dipole; > 0: a uniformly
// magnetised sphere, finite inside)}.
bool read_dipole(const Value& value, MagneticDipole* dipole) {
  const MapReader map(value, {"position", "moment", "radius"});
  if (!map.ok()) return false;
  return map.read_vector3("position", Need::kRequired, Range::finite(), &dipole->p_FD) &
         map.read_vector3("moment", Need::kRequired, Range::finite(), &dipole->m_F) &
         map.read_number("radius", Need::kOptional, Range::non_negative(), &dipole->radius_m);
}

}  // namespace

std::vector<MagneticDipole> read_dipoles(const Value& value) {
  std::vector<MagneticDipole> dipoles;
  if (const auto items = value.list()) {
    for (const Value& item : *items) {
      MagneticDipole dipole;
      if (read_dipole(item, &dipole)) dipoles.push_back(dipole);
    }
  }
  return dipoles;
}

const std::vector<std::string>& MagnetometerSensor::keys() {
  static const std::vector<std::string> keys = {"noise_stddev_nt", "resolution_nt", "range_ut", "hard_iron",
                                                "soft_iron"};
  return keys;
}

// White noise per sample, resolution and range in nT / uT, hard-iron dipoles in B, the soft-iron matrix
// in sensor axes.
MagnetometerSensor::Spec MagnetometerSensor::read(const SensorReader& reader) {
  const MapReader& map = reader.map;
  Spec spec;
  MagnetometerParams& p = spec.params;
  double noise_nt = 0.0, resolution_nt = 0.0, range_ut = 0.0;
  map.read_number("noise_stddev_nt", Need::kOptional, Range::non_negative(), &noise_nt);
  map.read_number("resolution_nt", Need::kOptional, Range::non_negative(), &resolution_nt);
  map.read_number("range_ut", Need::kOptional, Range::positive(), &range_ut);
  for (auto& axis : p.noise.axes) axis.white_noise_density = noise_nt * 1e-9 / std::sqrt(reader.rate_hz);
  p.noise.lsb = resolution_nt * 1e-9;
  if (range_ut > 0.0) p.noise.min = -(p.noise.max = range_ut * 1e-6);
  if (const auto hard_iron = map.optional("hard_iron")) p.dipoles_B = read_dipoles(*hard_iron);
  if (const auto soft_iron = map.optional("soft_iron")) {
    if (const auto values = soft_iron->numbers(9)) {
      p.soft_iron_S = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(values->data());
    }
  }
  return spec;
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

#include "hadal/sensors/imu_sensor.h"

#include <sensor_msgs.h>
#include <sensor_msgsPubSubTypes.h>

#include <algorithm>
#include <cmath>

#include "hadal/config/key_table.h"
#include "hadal/dds/time_msg.h"
#include "hadal/physics/ocean.h"
#include "hadal/sensors/sample_context.h"
#include "hadal/core/units.h"

namespace hadal::sensors {

using config::join_names;
using namespace config::keys;
using config::Need;
using config::quoted;

namespace {

using Spec = ImuSensor::Spec;

const config::KeyTable<Spec>& gyro_keys() {
  return config::declare_keys<Spec>([](config::KeyTable<Spec>& t) {
    t.describe("sensors[].imu.gyro", "the gyroscopes' figures; each overrides the preset's");
    const auto sheet = [](double ImuDatasheet::*field) {
      return [field](Spec& s) -> double& { return s.figures.sheet.*field; };
    };
    t.number("arw_deg_per_sqrt_h", sheet(&ImuDatasheet::gyro_arw_deg_per_sqrt_h)).unit("deg/√h")
        .range(Range::non_negative()).doc("angle random walk");
    t.number("bias_instability_deg_per_h", sheet(&ImuDatasheet::gyro_bias_instability_deg_per_h)).unit("deg/h")
        .range(Range::non_negative()).doc("bias instability B (the Allan floor is 0.664 B)");
    t.number("rrw_deg_per_h_per_sqrt_h", sheet(&ImuDatasheet::gyro_rrw_deg_per_h_per_sqrt_h)).unit("deg/h/√h")
        .range(Range::non_negative()).doc("rate random walk");
    t.number("scale_factor_ppm", sheet(&ImuDatasheet::gyro_scale_factor_ppm)).unit("ppm").range(Range::non_negative())
        .doc("1 sigma, drawn per run");
    t.number("misalignment_deg", sheet(&ImuDatasheet::gyro_misalignment_rad)).degrees()
        .range(Range::closed(0.0, 10.0)).doc("1 sigma, drawn per run");
    t.number("range_deg_per_s", [](Spec& s) -> double& { return s.figures.gyro_range_deg_per_s; }).unit("deg/s")
        .range(Range::positive()).default_text("none").doc("readings clip to +-range");
    t.number("resolution_deg_per_s", [](Spec& s) -> double& { return s.figures.gyro_resolution_deg_per_s; })
        .unit("deg/s").range(Range::non_negative()).doc("quantisation step; 0: none");
  });
}

const config::KeyTable<Spec>& accel_keys() {
  return config::declare_keys<Spec>([](config::KeyTable<Spec>& t) {
    t.describe("sensors[].imu.accel", "the accelerometers' figures; each overrides the preset's");
    t.number("vrw_m_per_s_per_sqrt_h", [](Spec& s) -> double& { return s.figures.sheet.accel_noise_density; })
        .convert(vrw_to_noise_density, [](double density) { return density * 60.0; }, "m/s/√h")
        .range(Range::non_negative()).doc("velocity random walk");
    t.number("bias_instability_mg", [](Spec& s) -> double& { return s.figures.sheet.accel_bias_instability_mps2; })
        .convert(milli_g_to_mps2, [](double mps2) { return mps2 / milli_g_to_mps2(1.0); }, "mg")
        .range(Range::non_negative()).doc("bias instability");
    t.number("scale_factor_ppm", [](Spec& s) -> double& { return s.figures.sheet.accel_scale_factor_ppm; }).unit("ppm")
        .range(Range::non_negative()).doc("1 sigma, drawn per run");
    t.number("misalignment_deg", [](Spec& s) -> double& { return s.figures.accel_misalignment_deg; }).unit("deg")
        .range(Range::closed(0.0, 10.0)).doc("1 sigma, drawn per run");
    t.number("range_g", [](Spec& s) -> double& { return s.figures.accel_range_g; }).unit("g")
        .range(Range::positive()).default_text("none").doc("readings clip to +-range");
    t.number("resolution_mg", [](Spec& s) -> double& { return s.figures.accel_resolution_mg; }).unit("mg")
        .range(Range::non_negative()).doc("quantisation step; 0: none");
  });
}

const config::KeyTable<Spec>& temperature_keys() {
  return config::declare_keys<Spec>([](config::KeyTable<Spec>& t) {
    t.describe("sensors[].imu.temperature", "drift (T - T_ref) k_T with the water's temperature at the sensor");
    t.number("reference_degc", &Spec::temperature_reference).unit("°C").range(Range::closed(-5.0, 60.0)).doc("T_ref");
    t.number("gyro_deg_per_h_per_degc", &Spec::gyro_temperature_coefficient)
        .convert(deg_per_h_to_rad_per_s, [](double rad_s) { return rad_s / deg_per_h_to_rad_per_s(1.0); }, "deg/h/°C")
        .doc("k_T of the gyroscopes, every axis");
    t.number("accel_mg_per_degc", &Spec::accel_temperature_coefficient)
        .convert(milli_g_to_mps2, [](double mps2) { return mps2 / milli_g_to_mps2(1.0); }, "mg/°C")
        .doc("k_T of the accelerometers, every axis");
  });
}

// The thruster whose blade passes shake the IMU: its index among the vehicle's actuators.
bool read_vibration_thruster(const config::Value& value, Spec& spec, SensorReader& reader) {
  const std::optional<std::string> name = value.string();
  if (!name) return false;
  std::vector<std::string> thruster_names;
  for (std::size_t i = 0; i < reader.actuator_names.size(); ++i) {
    if (reader.actuator_types[i] != "thruster") continue;
    thruster_names.push_back(reader.actuator_names[i]);
    if (reader.actuator_names[i] == *name) spec.vibration_thruster = static_cast<int>(i);
  }
  if (spec.vibration_thruster >= 0) return true;
  value.error("no thruster named " + config::quoted(*name) + " in this vehicle (" +
              (thruster_names.empty() ? std::string("it has none") : "thrusters: " + config::join_names(thruster_names)) +
              ")");
  return false;
}

const config::KeyTable<Spec, SensorReader>& vibration_keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].imu.vibration", "A sin(2 pi f t) on every axis, f the thruster's rotor speed x blades");
    t.custom("thruster", read_vibration_thruster, R"({"type": "string", "minLength": 1})", "string").required()
        .doc("a thruster of this vehicle");
    t.number("blades", &Spec::vibration_blades).range(Range::closed(1.0, 12.0)).doc("blade-pass frequency = blades x rotor speed");
    t.number("gyro_deg_per_s", &Spec::gyro_vibration_amplitude).convert(
         [](double deg_s) { return deg_s * kDegToRad; }, [](double rad_s) { return rad_s / kDegToRad; }, "deg/s")
        .range(Range::non_negative()).doc("amplitude A of the gyroscopes");
    t.number("accel_mg", &Spec::accel_vibration_amplitude)
        .convert(milli_g_to_mps2, [](double mps2) { return mps2 / milli_g_to_mps2(1.0); }, "mg")
        .range(Range::non_negative()).doc("amplitude A of the accelerometers");
  });
}

}  // namespace

// A data-sheet preset and/or figures in data-sheet units, converted by sensors/noise.h; temperature
// drift and thruster vibration.
SensorReach ImuSensor::reach(const Spec& /*spec*/) { return {}; }

const config::KeyTable<ImuSensor::Spec, SensorReader>& ImuSensor::keys() {
  return config::declare_keys<Spec, SensorReader>([](config::KeyTable<Spec, SensorReader>& t) {
    t.describe("sensors[].imu", "gyroscopes and accelerometers: the paper's error chain");
    t.preset("IMU", imu_presets(), [](Spec& spec, const config::Preset<ImuDatasheet>& p, SensorReader&) { spec.figures.sheet = p.figures; })
        .doc("a product (table below); without one, no noise");
    t.map("gyro", [](Spec& s) -> Spec& { return s; }, gyro_keys()).doc("gyroscope figures");
    t.map("accel", [](Spec& s) -> Spec& { return s; }, accel_keys()).doc("accelerometer figures");
    t.boolean("white_noise_only", [](Spec& s) -> bool& { return s.figures.white_noise_only; })
        .doc("keep only white noise (validation: the paper's white-noise-only model)");
    t.map("temperature", [](Spec& s) -> Spec& { return s; }, temperature_keys()).doc("temperature drift");
    t.map("vibration", [](Spec& s) -> Spec& { return s; }, vibration_keys()).doc("a thruster's vibration");
    // The triads from the figures.
    t.check([](const config::KeyReads&, Spec& spec, SensorReader&) {
      Figures f = spec.figures;
      ImuDatasheet& sheet = f.sheet;
      if (f.white_noise_only) {
        sheet.gyro_bias_instability_deg_per_h = 0.0;
        sheet.gyro_rrw_deg_per_h_per_sqrt_h = 0.0;
        sheet.gyro_scale_factor_ppm = 0.0;
        sheet.gyro_misalignment_rad = 0.0;
        sheet.accel_bias_instability_mps2 = 0.0;
        sheet.accel_scale_factor_ppm = 0.0;
        f.accel_misalignment_deg = 0.0;
      }
      const ImuNoiseParams params = imu_noise_params(sheet);
      spec.gyro = params.gyro;
      spec.accel = params.accel;
      spec.accel.misalignment_sigma = f.accel_misalignment_deg * kDegToRad;
      if (f.gyro_range_deg_per_s > 0.0) spec.gyro.min = -(spec.gyro.max = f.gyro_range_deg_per_s * kDegToRad);
      if (f.accel_range_g > 0.0) spec.accel.min = -(spec.accel.max = f.accel_range_g * kStandardGravity);
      spec.gyro.lsb = f.gyro_resolution_deg_per_s * kDegToRad;
      spec.accel.lsb = milli_g_to_mps2(f.accel_resolution_mg);
      return true;
    });
  });
}

ImuSensor::State ImuSensor::initial_state(const Spec& spec, const SensorSetup& setup) {
  State state;
  state.gyro = make_noise_state(spec.gyro, channel_key(setup.seed, setup.vehicle, setup.sensor, "gyro"));
  state.accel = make_noise_state(spec.accel, channel_key(setup.seed, setup.vehicle, setup.sensor, "accel"));
  return state;
}

void ImuSensor::sample(const SampleContext& context, const Spec& spec, State& state) {
  const RigidBodyState& body = context.body();
  const double dt = context.step_size;
  const Eigen::Matrix3d R_SW = context.R_WS().transpose();
  // Mean accelerations over the step that ends now (exact for Bullet's semi-implicit step).
  const Eigen::Vector3d p_WBcm = body.X_WB * context.p_BBcm;
  const Eigen::Vector3d v_WBcm = body.v_WB + body.w_WB.cross(p_WBcm - body.X_WB.translation());
  const Eigen::Vector3d a_WBcm = (v_WBcm - context.v_WBcm_step_start) / dt;
  const Eigen::Vector3d alpha_W = (body.w_WB - context.w_WB_step_start) / dt;
  const Eigen::Vector3d p_WS = context.p_WS();
  const Eigen::Vector3d r_W = p_WS - p_WBcm;
  const Eigen::Vector3d& w = body.w_WB;
  const Eigen::Vector3d a_WS = a_WBcm + alpha_W.cross(r_W) + w.cross(w.cross(r_W));
  const Eigen::Vector3d w_S = R_SW * w;
  const Eigen::Vector3d f_S = R_SW * (a_WS - context.world.gravity_W);
  // Temperature drift with the water's temperature at the sensor; thruster vibration.
  const double depth = std::max(context.ocean.depth(p_WS.z()), 0.0);
  const double dT = context.ocean.temperature(depth) - spec.temperature_reference;
  double vibration = 0.0;
  if (spec.vibration_thruster >= 0) {
    const auto& thruster = std::get<physics::ThrusterActuator::State>(
        context.vehicle().actuators[static_cast<std::size_t>(spec.vibration_thruster)]);
    const double f = spec.vibration_blades * std::abs(thruster.rotor_speed_rev_s);
    vibration = std::sin(2.0 * kPi * f * context.time);
  }
  const Eigen::Vector3d gyro_terms = Eigen::Vector3d::Constant(dT * spec.gyro_temperature_coefficient +
                                                               vibration * spec.gyro_vibration_amplitude);
  const Eigen::Vector3d accel_terms = Eigen::Vector3d::Constant(dT * spec.accel_temperature_coefficient +
                                                                vibration * spec.accel_vibration_amplitude);
  state.angular_velocity_S = measure(spec.gyro, state.gyro, w_S, context.period, gyro_terms);
  state.specific_force_S = measure(spec.accel, state.accel, f_S, context.period, accel_terms);
}

void ImuSensor::fill_message(const Spec& spec, const State& state, const MessageHeader& header, Message& msg) {
  msg.header().stamp(dds::to_time_msg(header.stamp));
  msg.header().frame_id(header.frame_id);
  msg.orientation().x(0.0);
  msg.orientation().y(0.0);
  msg.orientation().z(0.0);
  msg.orientation().w(1.0);
  msg.orientation_covariance().fill(0.0);
  msg.orientation_covariance()[0] = -1.0;
  msg.angular_velocity().x(state.angular_velocity_S.x());
  msg.angular_velocity().y(state.angular_velocity_S.y());
  msg.angular_velocity().z(state.angular_velocity_S.z());
  msg.linear_acceleration().x(state.specific_force_S.x());
  msg.linear_acceleration().y(state.specific_force_S.y());
  msg.linear_acceleration().z(state.specific_force_S.z());
  msg.angular_velocity_covariance().fill(0.0);
  msg.linear_acceleration_covariance().fill(0.0);
  for (int a = 0; a < 3; ++a) {
    const double n_gyro = spec.gyro.axes[a].white_noise_density;
    const double n_accel = spec.accel.axes[a].white_noise_density;
    msg.angular_velocity_covariance()[4 * a] = n_gyro * n_gyro * header.rate_hz;
    msg.linear_acceleration_covariance()[4 * a] = n_accel * n_accel * header.rate_hz;
  }
}

// --- presets -------------------------------------------------------------------------------------------

const config::Presets<ImuDatasheet>& imu_presets() {
  // Figures as the CSV's rows give them, converted where its unit is not the field's; imu_sensor_test.cc
  // recomputes the gyroscope figures from the CSV.
  static const config::Presets<ImuDatasheet> presets = {
      {.id = "honeywell_hg1700",
       .product = "Honeywell HG1700 (higher-end AG variants)",
       .source = "imu_datasheet_figures.csv: Honeywell brochure N61-1619-000-001 (ARW 0.125 deg/sqrt(h) max, bias "
                 "instability 1.0 deg/h 1 sigma, VRW 0.065 ft/s/sqrt(h) max, accel bias 1 mg 1 sigma); scale factors "
                 "150 ppm gyro / 300 ppm accel from a REMUS-100 design note",
       .figures = {.gyro_arw_deg_per_sqrt_h = 0.125,
                   .gyro_bias_instability_deg_per_h = 1.0,
                   .gyro_scale_factor_ppm = 150.0,
                   .accel_noise_density = vrw_to_noise_density(0.065 * kFootInMeters),
                   .accel_bias_instability_mps2 = milli_g_to_mps2(1.0),
                   .accel_scale_factor_ppm = 300.0}},
      {.id = "honeywell_hg9900",
       .product = "Honeywell HG9900",
       .source = "imu_datasheet_figures.csv: Honeywell brochure N61-1638-000-000 (ARW 0.002 max, bias instability "
                 "0.0035 deg/h, no VRW listed, accel bias 25 ug; accel SF 100 ppm, gyro SF 5 ppm)",
       .figures = {.gyro_arw_deg_per_sqrt_h = 0.002,
                   .gyro_bias_instability_deg_per_h = 0.0035,
                   .gyro_scale_factor_ppm = 5.0,
                   .accel_bias_instability_mps2 = micro_g_to_mps2(25.0),
                   .accel_scale_factor_ppm = 100.0}},
      {.id = "safran_primus_200",
       .product = "Safran/Sagem Primus 200",
       .source = "imu_datasheet_figures.csv: vendor spec sheet (ARW 0.004, bias instability 0.05 deg/h, accel "
                 "noise 60 ug/sqrt(Hz), accel bias 2 mg rms); the row's \"=5.886e-5 m/s^1.5\" is a factor 10 "
                 "off (60 ug/sqrt(Hz) = 5.884e-4 m/s^2/sqrt(Hz)): the ug figure is used",
       .figures = {.gyro_arw_deg_per_sqrt_h = 0.004,
                   .gyro_bias_instability_deg_per_h = 0.05,
                   .accel_noise_density = micro_g_per_sqrt_hz_to_noise_density(60.0),
                   .accel_bias_instability_mps2 = milli_g_to_mps2(2.0)}},
      {.id = "sensonor_stim300",
       .product = "Sensonor STIM300 (10 g accel)",
       .source = "imu_datasheet_figures.csv: Sensonor TS1524 r9 datasheet (ARW 0.15, bias instability 0.5 deg/h, "
                 "VRW 0.06 m/s/sqrt(h), accel bias 0.05 mg, gyro misalignment 1 mrad, accelerometer range 10 g)",
       .figures = {.gyro_arw_deg_per_sqrt_h = 0.15,
                   .gyro_bias_instability_deg_per_h = 0.5,
                   .gyro_misalignment_rad = 1e-3,
                   .accel_noise_density = vrw_to_noise_density(0.06),
                   .accel_bias_instability_mps2 = milli_g_to_mps2(0.05),
                   .accel_range_mps2 = 10.0 * kStandardGravity}},
      {.id = "xsens_mti_300",
       .product = "Xsens MTi-300 (MTi-100 series)",
       .source = "imu_datasheet_figures.csv: noise densities as used in a public EKF citing the Xsens MTi-300 "
                 "datasheet (ARW 0.6 deg/sqrt(h) = 0.01 deg/s/sqrt(Hz), accel 60 ug/sqrt(Hz)); its in-run bias "
                 "figures are unverified and left out",
       .figures = {.gyro_arw_deg_per_sqrt_h = 0.6,
                   .accel_noise_density = micro_g_per_sqrt_hz_to_noise_density(60.0)}},
  };
  return presets;
}

ImuNoiseParams imu_noise_params(const ImuDatasheet& sheet, double bank_tau_min_s, double bank_tau_max_s) {
  ImuNoiseParams params;
  AxisNoiseParams gyro;
  gyro.white_noise_density = arw_to_noise_density(sheet.gyro_arw_deg_per_sqrt_h);
  gyro.bias_random_walk_density = rrw_to_random_walk_density(sheet.gyro_rrw_deg_per_h_per_sqrt_h);
  if (sheet.gyro_bias_instability_deg_per_h > 0.0) {
    gyro.gauss_markov = bias_instability_to_gauss_markov_bank(
        deg_per_h_to_rad_per_s(sheet.gyro_bias_instability_deg_per_h), bank_tau_min_s, bank_tau_max_s);
  }
  params.gyro.axes = {gyro, gyro, gyro};
  params.gyro.scale_factor_sigma = sheet.gyro_scale_factor_ppm * 1e-6;
  params.gyro.misalignment_sigma = sheet.gyro_misalignment_rad;

  AxisNoiseParams accel;
  accel.white_noise_density = sheet.accel_noise_density;
  if (sheet.accel_bias_instability_mps2 > 0.0) {
    accel.gauss_markov =
        bias_instability_to_gauss_markov_bank(sheet.accel_bias_instability_mps2, bank_tau_min_s, bank_tau_max_s);
  }
  params.accel.axes = {accel, accel, accel};
  params.accel.scale_factor_sigma = sheet.accel_scale_factor_ppm * 1e-6;
  params.accel.min = -sheet.accel_range_mps2;
  params.accel.max = sheet.accel_range_mps2;
  return params;
}

}  // namespace hadal::sensors

#include "hadal/physics/water_spec.h"

#include <cmath>
#include <limits>
#include <string>

#include "hadal/config/key_table.h"
#include "hadal/physics/seawater.h"

namespace hadal::physics {
namespace {

using namespace config::keys;

const Range kTemperatureDegC = Range::closed(-2.5, 40.0);
// Liquid water of any salinity Hadal models: fresh water at 40 °C (992) to brine pools (~1200). A value in g/cm³
// or t/m³ (1.025) is out of it.
const Range kWaterDensity = Range::closed(900.0, 1300.0);
const Range kSalinity = Range::closed(0.0, 42.0);

const KeyTable<CurrentSpec>& shear_keys() {
  return declare_keys<CurrentSpec>([](KeyTable<CurrentSpec>& t) {
    t.describe("world.water.current.shear", "exponentially decaying shear");
    t.vector("surface", &CurrentSpec::shear_surface_W).required().unit("m/s").doc("the shear at the surface, in W");
    t.number("decay_depth", &CurrentSpec::shear_decay_depth).required().unit("m").range(Range::positive())
        .doc("its e-folding depth");
  });
}

const KeyTable<CurrentSpec>& gauss_markov_keys() {
  return declare_keys<CurrentSpec>([](KeyTable<CurrentSpec>& t) {
    t.describe("world.water.current.gauss_markov", "first-order Gauss-Markov current, seeded by world.seed");
    t.vector("sigma", &CurrentSpec::gauss_markov_sigma_W).required().unit("m/s").range(Range::non_negative())
        .doc("stationary standard deviation per W axis");
    // A slowly varying current: below 1 s it would be turbulence, and the lazily generated record (64
    // samples per time constant) would grow large.
    t.number("time_constant_s", &CurrentSpec::gauss_markov_time_constant).required().unit("s")
        .range(Range::closed(1.0, 1e7)).doc("correlation time");
  });
}

const KeyTable<CurrentSpec>& current_keys() {
  return declare_keys<CurrentSpec>([](KeyTable<CurrentSpec>& t) {
    t.describe("world.water.current", "v(p_W, t) = uniform + shear.surface exp(-d / shear.decay_depth) + g(t), in W");
    t.vector("uniform", &CurrentSpec::uniform_W).unit("m/s").doc("uniform current in W");
    t.map("shear", [](CurrentSpec& c) -> CurrentSpec& { return c; }, shear_keys())
        .doc("a shear decaying exponentially with depth");
    t.map("gauss_markov", [](CurrentSpec& c) -> CurrentSpec& { return c; }, gauss_markov_keys())
        .doc("a first-order Gauss-Markov term g(t) per axis, the same everywhere, seeded by `world.seed`");
  });
}

const KeyTable<CtdSample>& ctd_row_keys() {
  return declare_keys<CtdSample>([](KeyTable<CtdSample>& t) {
    t.describe("world.water.ctd[]", "one row of a CTD cast");
    t.number("depth", &CtdSample::depth).required().unit("m").range(Range::closed(0.0, kDeepestOcean_m))
        .rule("greater than the previous row's").doc("below the surface");
    t.number("temperature_degc", &CtdSample::temperature).required().unit("°C").range(kTemperatureDegC)
        .doc("in-situ temperature, ITS-90");
    t.number("salinity", &CtdSample::salinity).required().unit("PSS-78").range(kSalinity).doc("practical salinity");
  });
}

// The cast: rows of ctd_row_keys(), depths strictly increasing. A bad cast leaves none (reported).
bool read_ctd(const Value& value, WaterSpec& water) {
  const auto rows = value.list();
  if (!rows) return false;
  if (rows->size() < 2) {
    value.error("needs at least 2 rows (got " + std::to_string(rows->size()) + ")");
    return false;
  }
  bool ok = true;
  // The previous row's depth, NaN when it was invalid (a NaN, not an optional: GCC 12 at -O2 misreads the
  // optional's storage as uninitialised in C++20).
  double previous_depth = std::numeric_limits<double>::quiet_NaN();
  NoContext none;
  for (const Value& row_value : *rows) {
    const MapReader row(row_value, ctd_row_keys().names());
    if (!row.ok()) {
      ok = false;
      previous_depth = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    CtdSample sample;
    std::vector<std::string> failed;
    ok &= ctd_row_keys().read_map(row, &sample, none, &failed);
    const bool depth_ok = std::find(failed.begin(), failed.end(), "depth") == failed.end();
    if (depth_ok && !std::isnan(previous_depth) && !(sample.depth > previous_depth)) {
      row.optional("depth")->error("must be greater than the previous row's depth (" +
                                   config::format_number(previous_depth) + ")");
      ok = false;
    }
    previous_depth = depth_ok ? sample.depth : std::numeric_limits<double>::quiet_NaN();
    water.ctd.push_back(sample);
  }
  if (!ok) water.ctd.clear();
  return ok;
}

}  // namespace

const KeyTable<WaterSpec>& water_keys() {
  return declare_keys<WaterSpec>([](KeyTable<WaterSpec>& t) {
    t.describe("world.water", "the water column: density, temperature, salinity, pressure, current");
    t.number("surface_z", &WaterSpec::surface_z).unit("m").doc("height of the water surface in W");
    t.choice("density_model", &WaterSpec::density_model,
             {{"constant", DensityModel::kConstant, "rho = density"},
              {"ramp", DensityModel::kRamp, "the paper's pycnocline ramp"},
              {"ctd", DensityModel::kCtd, "a temperature/salinity cast and EOS-80"}})
        .selects("density_model")
        .doc("how density varies with depth");
    t.number("density", &WaterSpec::density).only_for({"constant"}).unit("kg/m³").range(kWaterDensity)
        .doc("the water's density (fresh ~1000, sea 1020–1050; 1.025 would be g/cm³)");
    t.number("rho0", &WaterSpec::rho0).only_for({"ramp"}).unit("kg/m³").range(kWaterDensity)
        .doc("density at the surface");
    t.number("pycnocline_depth", &WaterSpec::pycnocline_depth).only_for({"ramp"}).unit("m")
        .range(Range::left_open(0.0, kDeepestOcean_m)).doc("depth at which the ramp ends");
    t.number("pycnocline_density_increase", &WaterSpec::pycnocline_density_increase).only_for({"ramp"})
        .unit("kg/m³").range(Range::closed(0.0, 100.0)).doc("density gained down to pycnocline_depth (+0.3 % by default)");
    t.list("ctd", &WaterSpec::ctd, ctd_row_keys()).only_for({"ctd"}).required_for({"ctd"}).min_items(2, "rows")
        .read_with([](const Value& value, WaterSpec& water, NoContext&) { return read_ctd(value, water); })
        .doc("the cast, depths strictly increasing");
    t.number("temperature_degc", &WaterSpec::temperature).only_for({"constant", "ramp"}).unit("°C")
        .range(kTemperatureDegC).doc("temperature (ITS-90) of water without a cast");
    t.number("salinity", &WaterSpec::salinity).only_for({"constant", "ramp"}).unit("PSS-78").range(kSalinity)
        .doc("practical salinity of water without a cast");
    t.number("atmospheric_pressure", &WaterSpec::atmospheric_pressure).unit("Pa").range(Range::closed(0.0, 1e7))
        .doc("pressure at the surface");
    t.number("bulk_modulus", &WaterSpec::bulk_modulus).unit("Pa").range(Range::positive())
        .doc("K in the added-mass compression factor kappa(d) = 1 - p(d)/K");
    t.number("ph", &WaterSpec::ph).range(Range::closed(6.0, 9.0))
        .doc("the water's pH, in the sonars' sound absorption (Francois-Garrison's boric acid term)");
    t.map("current", &WaterSpec::current, current_keys()).doc("the current, zero by default");
    // The lumped fluid model sees one density: rho0 (ramp), the EOS-80 surface density of the cast (ctd).
    t.check([](const config::KeyReads&, WaterSpec& water, NoContext&) {
      if (water.density_model == DensityModel::kRamp) water.density = water.rho0;
      if (water.density_model == DensityModel::kCtd && !water.ctd.empty()) {
        const CtdSample& top = water.ctd.front();
        water.density = density_eos80(top.salinity, its90_to_ipts68(top.temperature), 0.0);
      }
      return true;
    });
  });
}

}  // namespace hadal::physics

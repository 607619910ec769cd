#include "hadal/render/optics_spec.h"

#include <string>

#include "hadal/config/key_table.h"
#include "hadal/render/water_presets.h"

namespace hadal::render {
namespace {

using namespace config::keys;

// Pure water plus a little scattering: b = 0.037 /m per channel (Petzold's clear ocean at 530 nm: Mobley,
// Light and Water (1994), Table 3.10), Henyey-Greenstein g 0.924, forward scatter within 10 deg
// (render/forward_scatter.h); daylight E0 [W/m^2 per channel] at the surface decaying by Jerlov type I's Kd.
OpticsSpec default_optics() {
  OpticsSpec optics;
  optics.water.absorption_per_m = pure_water_absorption_per_m();
  optics.water.scattering_per_m = Rgb::Constant(0.037);
  optics.water.forward_scatter_max_angle_rad = 10.0 * kDegToRad;
  optics.daylight.surface_irradiance_W_per_m2 = Rgb(150.0, 170.0, 160.0);
  optics.daylight.Kd_per_m = jerlov_Kd_per_m(JerlovType::kI);
  return optics;
}

const KeyTable<OpticsSpec>& daylight_keys() {
  return declare_keys<OpticsSpec>(default_optics(), [](KeyTable<OpticsSpec>& t) {
    t.describe("world.optics.daylight", "daylight from the surface");
    t.vector("surface_irradiance", [](OpticsSpec& o) -> Rgb& { return o.daylight.surface_irradiance_W_per_m2; })
        .unit("W/m²").range(Range::closed(0.0, 1e5))
        .doc("downwelling irradiance just below the surface, per band; decays with depth by Kd");
    std::string names;
    for (JerlovType type : {JerlovType::kI, JerlovType::kIA, JerlovType::kIB, JerlovType::kII, JerlovType::kIII,
                            JerlovType::k1C, JerlovType::k3C, JerlovType::k5C, JerlovType::k7C, JerlovType::k9C}) {
      names += (names.empty() ? "\"" : ", \"") + std::string(to_string(type)) + "\"";
    }
    t.custom(
         "jerlov_type",
         [](const Value& value, OpticsSpec& optics, NoContext&) {
           const std::optional<std::string> name = value.string();
           if (!name) return false;
           JerlovType jerlov = JerlovType::kI;
           if (!jerlov_type_from_string(*name, &jerlov)) {
             value.error("unknown Jerlov water type " + config::quoted(*name) +
                         " (one of I, IA, IB, II, III, 1C, 3C, 5C, 7C, 9C)");
             return false;
           }
           optics.daylight.Kd_per_m = jerlov_Kd_per_m(jerlov);
           return true;
         },
         R"({"enum": [)" + names + "]}", "string")
        .default_text("`I`")
        .doc("Kd per band by Jerlov water type (`docs/reference/optics/`): I, IA, IB, II, III, 1C, 3C, 5C, 7C, 9C; "
             "below a few hundred metres daylight is black");
    t.number("refractive_index", [](OpticsSpec& o) -> double& { return o.daylight.refractive_index; })
        .range(Range::closed(1.0, 2.0))
        .doc("the water's, for the surface seen from below: Snell's window of half-angle asin(1 / n) (48.3 deg for "
             "seawater's 1.34; total internal reflection outside it)");
  });
}

const KeyTable<SedimentPattern>& seabed_pattern_keys() {
  return declare_keys<SedimentPattern>([](KeyTable<SedimentPattern>& t) {
    t.describe("world.optics.seabed_pattern",
               "patches of lighter and darker sediment (render/sediment_pattern.h), seeded by world.seed");
    t.number("amplitude", &SedimentPattern::amplitude).required().range(Range::closed(0.0, 1.0))
        .doc("the albedo varies by up to +- this fraction");
    t.number("scale", &SedimentPattern::scale_m).unit("m").range(Range::left_open(0.0, 1e4))
        .doc("size of the largest patches");
    t.number("octaves", &SedimentPattern::octaves).range(Range::closed(1.0, 8.0))
        .doc("each adds detail half the size of the one before");
  });
}

const KeyTable<MarineSnow>& marine_snow_keys() {
  return declare_keys<MarineSnow>([](KeyTable<MarineSnow>& t) {
    t.describe("world.optics.marine_snow",
               "particles fixed in the water that glitter in the lights (render/marine_snow.h), seeded by "
               "world.seed");
    t.number("density", &MarineSnow::density_per_m3).required().unit("1/m³").range(Range::closed(0.0, 1e5))
        .doc("particles per cubic metre");
    t.number("radius", &MarineSnow::radius).unit("m").range(Range::left_open(0.0, 0.1))
        .doc("mean radius (uniform in 0.5-1.5 x it)");
    t.number("max_range", &MarineSnow::max_range).unit("m").range(Range::left_open(0.0, 50.0))
        .doc("drawn within this distance of the camera");
    t.number("albedo", &MarineSnow::albedo).range(Range::closed(0.0, 1.0)).doc("of a particle");
  });
}

}  // namespace

const KeyTable<OpticsSpec>& optics_keys() {
  return declare_keys<OpticsSpec>(default_optics(), [](KeyTable<OpticsSpec>& t) {
    t.describe("world.optics", "what cameras see: the water's optics, daylight, albedos");
    t.vector("absorption", [](OpticsSpec& o) -> Rgb& { return o.water.absorption_per_m; }).unit("1/m")
        .range(Range::closed(0.0, 100.0))
        .doc("absorption a per band; default pure water (Pope & Fry 1997, band means)");
    t.vector("scattering", [](OpticsSpec& o) -> Rgb& { return o.water.scattering_per_m; }).unit("1/m")
        .range(Range::closed(0.0, 100.0)).doc("scattering b per band; default Petzold's clear ocean at 530 nm");
    t.number("phase_g", [](OpticsSpec& o) -> double& { return o.water.phase_g; }).range(Range::open(-1.0, 1.0))
        .doc("Henyey-Greenstein asymmetry of single-scattering backscatter (Petzold's mean cosine)");
    t.number("forward_scatter_max_angle_deg",
             [](OpticsSpec& o) -> double& { return o.water.forward_scatter_max_angle_rad; })
        .degrees().range(Range::closed(0.0, 30.0))
        .doc("light from a surface scattered within this angle of forward still reaches the camera, as a halo "
             "(render/forward_scatter.h); 0 turns it off");
    t.map("daylight", [](OpticsSpec& o) -> OpticsSpec& { return o; }, daylight_keys())
        .doc("daylight from the surface");
    t.vector("seabed_albedo", &OpticsSpec::seabed_albedo).range(Range::closed(0.0, 1.0))
        .doc("sediment, per band; the mean when seabed_pattern is given");
    t.map("seabed_pattern", &OpticsSpec::seabed_pattern, seabed_pattern_keys())
        .doc("a sediment pattern on the seabed; none by default (uniform)");
    t.vector("vehicle_albedo", &OpticsSpec::vehicle_albedo).range(Range::closed(0.0, 1.0))
        .doc("every hull (survey yellow)");
    t.map("marine_snow", &OpticsSpec::marine_snow, marine_snow_keys()).doc("marine snow; none by default");
  });
}

}  // namespace hadal::render

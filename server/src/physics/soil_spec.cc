#include "hadal/physics/soil_spec.h"

#include <string>
#include <vector>

#include "hadal/config/key_table.h"
#include "hadal/physics/soil_map.h"
#include "hadal/physics/soil_presets.h"

namespace hadal::physics {
namespace {

using namespace config::keys;

constexpr const char* kDefaultPreset = "deep_sea_ooze";

// A soil's keys: a preset (physics/soil_presets.h), then any of its parameters, in SI. S is the world's
// soil or one of its regions: both have `preset` and `parameters`.
template <class S>
void declare_soil_keys(KeyTable<S>& t) {
  t.preset("soil", soil_presets(), [](S& soil, const config::Preset<SoilParameters>& p, NoContext&) {
     soil.preset = p.id;
     soil.parameters = p.figures;
   }).default_choice(kDefaultPreset).doc("a published soil (table below); the other keys override its parameters");
  const auto parameter = [](double SoilParameters::*field) {
    return [field](S& soil) -> double& { return soil.parameters.*field; };
  };
  t.number("sinkage_exponent", parameter(&SoilParameters::sinkage_exponent)).range(Range::left_open(0.0, 3.0))
      .default_text("the preset's").doc("n");
  t.number("k_c", parameter(&SoilParameters::k_c)).unit("N/m^(n+1)").range(Range::closed(0.0, 1e9))
      .default_text("the preset's").doc("cohesive modulus of deformation");
  t.number("k_phi", parameter(&SoilParameters::k_phi)).unit("N/m^(n+2)").range(Range::closed(0.0, 1e10))
      .default_text("the preset's").doc("frictional modulus of deformation (not both 0)");
  t.number("cohesion", parameter(&SoilParameters::cohesion)).unit("Pa").range(Range::closed(0.0, 1e7))
      .default_text("the preset's").doc("c");
  t.number("friction_angle_deg", parameter(&SoilParameters::friction_angle)).degrees().range(Range::closed(0.0, 60.0))
      .default_text("the preset's").doc("phi");
  t.number("shear_deformation_modulus", parameter(&SoilParameters::shear_deformation_modulus)).unit("m")
      .range(Range::left_open(0.0, 1.0)).default_text("the preset's")
      .doc("K: the shear reaches 63 % of tau_max after a slip of K");
  t.number("damping", parameter(&SoilParameters::damping)).unit("Pa s/m").range(Range::closed(0.0, 1e9))
      .doc("c_d, normal damping per bearing area (capped per vehicle at c_d A dt <= m, so it never destabilises a "
           "light body)");
  t.number("shear_damping_time", parameter(&SoilParameters::shear_damping_time)).unit("s")
      .range(Range::closed(0.0, 1.0))
      .doc("eta: damping of the elastic shear, eta tau_max e^(-j/K) / K per area and unit slip speed (vanishes as the "
           "soil yields)");
  t.check([](const KeyReads& reads, S& soil, NoContext&) {
    const SoilParameters& p = soil.parameters;
    if (p.k_c == 0.0 && p.k_phi == 0.0 && (reads.has("k_c") || reads.has("k_phi"))) {
      reads.error_at_key(reads.has("k_phi") ? "k_phi" : "k_c", "k_c and k_phi are both 0: the soil would bear nothing");
      return false;
    }
    return true;
  });
}

SoilParameters ooze() { return config::find_preset(soil_presets(), kDefaultPreset)->figures; }

const KeyTable<SoilSpec::Region>& region_keys() {
  return declare_keys<SoilSpec::Region>(SoilSpec::Region{kDefaultPreset, ooze()}, [](KeyTable<SoilSpec::Region>& t) {
    t.describe("world.soil.regions[]", "a soil by region: the keys of world.soil but regions and map");
    declare_soil_keys(t);
  });
}

struct SoilMapSpec {
  std::string file;
  double meters_per_pixel = 0.0;
  Eigen::Vector2d center_W = Eigen::Vector2d::Zero();
};

const KeyTable<SoilMapSpec>& map_keys() {
  return declare_keys<SoilMapSpec>([](KeyTable<SoilMapSpec>& t) {
    t.describe("world.soil.map", "where each region is: an image of region numbers");
    t.file("file", &SoilMapSpec::file).required()
        .doc("an 8-bit single-channel PNG or TIFF whose pixel value k names regions[k-1], 0 the world's soil");
    t.number("meters_per_pixel", &SoilMapSpec::meters_per_pixel).required().unit("m")
        .range(Range::left_open(0.0, 1e6)).doc("pixel spacing; image row 0 is the north (+y) edge");
    t.vector("center", &SoilMapSpec::center_W).unit("m").doc("[x, y] in W of the image's centre");
  });
}

}  // namespace

const KeyTable<SoilSpec>& soil_keys() {
  return declare_keys<SoilSpec>(SoilSpec{kDefaultPreset, ooze(), {}, nullptr}, [](KeyTable<SoilSpec>& t) {
    t.describe("world.soil", "the seabed's soil under vehicles with seabed_contact: soil");
    declare_soil_keys(t);
    t.list("regions", &SoilSpec::regions, region_keys())
        .read_with([](const Value& value, SoilSpec& soil, NoContext& none) {
          const std::optional<std::vector<Value>> list = value.list();
          if (!list) return false;
          bool ok = true;
          if (list->empty()) {
            value.error("must list at least one soil (or leave regions out)");
            ok = false;
          }
          if (list->size() > 255) {
            value.error("at most 255 regions (a map pixel is 8 bits; 0 is the world's soil)");
            ok = false;
          }
          // A malformed entry (reported) still holds its place, so the map's numbers keep their meaning.
          for (const Value& entry : *list) {
            SoilSpec::Region region = region_keys().defaults();
            ok &= region_keys().read(entry, &region, none);
            soil.regions.push_back(region);
          }
          return ok;
        })
        .doc("other soils, at most 255, each starting from `deep_sea_ooze`; needs `map`");
    t.custom(
         "map",
         [](const Value& value, SoilSpec& soil, NoContext& none) {
           SoilMapSpec image;
           if (!map_keys().read(value, &image, none)) return false;
           if (soil.regions.empty()) return true;  // reported by the check
           const SoilMapLoad load = load_soil_region_map(image.file, image.meters_per_pixel, image.center_W.head<2>(),
                                                         soil.regions.size());
           if (!load.map) {
             const YAML::Node file = value.node()["file"];
             value.in_same_file(file, config::child_path(value.path(), "file"), file.Mark()).error(load.error);
             return false;
           }
           soil.map = load.map;
           return true;
         },
         "", "map")
        .keys_of(map_keys())
        .doc("where each region is (image row 0 the north (+y) edge, each pixel a square cell); needs `regions`");
    t.check([](const KeyReads& reads, SoilSpec&, NoContext&) {
      if (reads.has("regions") && !reads.has("map")) {
        reads.error_at_key("regions", "regions need a `map` that says where each one is");
        return false;
      }
      if (reads.has("map") && !reads.has("regions")) {
        reads.error_at_key("map", "a soil map places `regions`, and there are none");
        return false;
      }
      return true;
    });
  });
}

}  // namespace hadal::physics

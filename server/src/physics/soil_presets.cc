#include "hadal/physics/soil_presets.h"

#include "hadal/core/units.h"

namespace hadal::physics {

namespace {

// A row of the reference tables in their units: k_c [kN/m^(n+1)], k_phi [kN/m^(n+2)], c [kPa],
// phi [deg], K [m].
SoilPreset preset(std::string name, std::string row, double n, double k_c_kN, double k_phi_kN, double c_kPa,
                  double phi_deg, double K_m, std::string note = {}) {
  SoilPreset out;
  out.name = std::move(name);
  out.table_row = std::move(row);
  out.soil.sinkage_exponent = n;
  out.soil.k_c = 1e3 * k_c_kN;
  out.soil.k_phi = 1e3 * k_phi_kN;
  out.soil.cohesion = 1e3 * c_kPa;
  out.soil.friction_angle = phi_deg * kDegToRad;
  out.soil.shear_deformation_modulus = K_m;
  out.note = std::move(note);
  return out;
}

// K where the table has none: Wong (Theory of Ground Vehicles, sec. 2.4) gives ~6 mm for clay at
// maximum compaction and 10-25 mm for firm to loose sand; the clays take the first, the loam the second's
// loose end. Assumptions, not measurements: the note says so.
constexpr double kClayK = 0.006;
constexpr double kLoamK = 0.025;

}  // namespace

const std::vector<SoilPreset>& soil_presets() {
  static const std::vector<SoilPreset> presets = {
      preset("deep_sea_ooze", "Deep-sea ooze (calibrated)", 0.8, 4.0, 30.0, 3.0, 5.0, 0.03,
             "calibrated to published sinkage, ground pressure and vane strength, not measured "
             "(docs/reference/terramechanics/deep_sea_ooze.md)"),
      preset("dry_sand", "Dry sand (Land Locomotion Lab; Wong Table 2.3)", 1.1, 0.99, 1528.43, 1.04, 28.0, 0.0175,
             "K 17.5 mm: the middle of the table's 10-25 mm (firm to loose)"),
      preset("sandy_loam", "Sandy loam (LLL 15% moisture; Wong Table 2.3)", 0.7, 5.27, 1515.04, 1.72, 29.0, kLoamK,
             "c and phi unverified in the table; K assumed 25 mm"),
      preset("clayey_soil", "Clayey soil (Thailand, 38% moisture; Wong Table 2.3)", 0.5, 13.19, 692.15, 4.14, 13.0,
             0.006),
      preset("lete_sand", "LETE sand", 0.793, 102.0, 5301.0, 1.3, 31.1, 0.012),
      preset("lunar_soil", "Lunar soil (Ding et al. 2015 Table I)", 1.0, 1.4, 820.0, 0.17, 35.0, 0.018),
      preset("hit_lss1", "HIT-LSS1 lunar simulant", 1.1, 15.6, 2407.4, 0.25, 31.9, 0.010),
      preset("heavy_clay_25", "Heavy clay (WES) 25% moisture", 0.13, 12.70, 1555.95, 68.95, 34.0, kClayK,
             "row unverified in the table; K assumed 6 mm"),
      preset("heavy_clay_40", "Heavy clay (WES) 40% moisture", 0.11, 1.84, 103.27, 20.69, 6.0, kClayK,
             "row unverified in the table; K assumed 6 mm"),
      preset("lean_clay_22", "Lean clay (WES) 22% moisture", 0.2, 16.43, 1724.69, 68.95, 20.0, kClayK,
             "row unverified in the table; K assumed 6 mm"),
      preset("lean_clay_32", "Lean clay (WES) 32% moisture", 0.15, 1.52, 119.61, 13.79, 11.0, kClayK,
             "row unverified in the table; K assumed 6 mm"),
      preset("clayey_soil_55", "Clayey soil (Thailand) 55% moisture", 0.7, 16.03, 1262.53, 2.07, 10.0, kClayK,
             "row unverified in the table; K assumed 6 mm"),
  };
  return presets;
}

const SoilPreset* find_soil_preset(std::string_view name) {
  for (const SoilPreset& p : soil_presets()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

std::string soil_preset_names() {
  std::string names;
  for (const SoilPreset& p : soil_presets()) names += (names.empty() ? "" : ", ") + p.name;
  return names;
}

}  // namespace hadal::physics

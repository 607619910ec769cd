#include "hadal/physics/soil_presets.h"

#include "hadal/core/units.h"

namespace hadal::physics {
namespace {

// A row of the reference tables in their units.
struct TableRow {
  double n = 0.0;
  double k_c_kN = 0.0;    // [kN/m^(n+1)]
  double k_phi_kN = 0.0;  // [kN/m^(n+2)]
  double c_kPa = 0.0;
  double phi_deg = 0.0;
  double K_m = 0.0;
};

// The row in SI; damping and shear_damping_time at their defaults.
SoilParameters si(const TableRow& row) {
  SoilParameters soil;
  soil.sinkage_exponent = row.n;
  soil.k_c = 1e3 * row.k_c_kN;
  soil.k_phi = 1e3 * row.k_phi_kN;
  soil.cohesion = 1e3 * row.c_kPa;
  soil.friction_angle = row.phi_deg * kDegToRad;
  soil.shear_deformation_modulus = row.K_m;
  return soil;
}

// K where the table has none: Wong (Theory of Ground Vehicles, sec. 2.4) gives ~6 mm for clay at
// maximum compaction and 10-25 mm for firm to loose sand; the clays take the first, the loam the second's
// loose end. Assumptions, not measurements: the sources say so.
constexpr double kClayK = 0.006;
constexpr double kLoamK = 0.025;

constexpr const char* kUnverifiedRowClayK = "bekker_parameters.csv; row unverified in the table; K assumed 6 mm";

}  // namespace

const config::Presets<SoilParameters>& soil_presets() {
  static const config::Presets<SoilParameters> presets = {
      {.id = "deep_sea_ooze",
       .product = "Deep-sea ooze (calibrated)",
       .source = "deep_sea_sediment.csv: calibrated to published sinkage, ground pressure and vane strength, not "
                 "measured (justified in deep_sea_ooze.md beside it)",
       .figures = si({.n = 0.8, .k_c_kN = 4.0, .k_phi_kN = 30.0, .c_kPa = 3.0, .phi_deg = 5.0, .K_m = 0.03})},
      {.id = "dry_sand",
       .product = "Dry sand (Land Locomotion Lab; Wong Table 2.3)",
       .source = "bekker_parameters.csv (Wong, Theory of Ground Vehicles, Table 2.3); K 17.5 mm: the middle of the row's "
                 "10-25 mm (firm to loose)",
       .figures = si({.n = 1.1, .k_c_kN = 0.99, .k_phi_kN = 1528.43, .c_kPa = 1.04, .phi_deg = 28.0, .K_m = 0.0175})},
      {.id = "sandy_loam",
       .product = "Sandy loam (LLL 15% moisture; Wong Table 2.3)",
       .source = "bekker_parameters.csv (Wong Table 2.3); c and phi unverified in the table; K assumed 25 mm",
       .figures = si({.n = 0.7, .k_c_kN = 5.27, .k_phi_kN = 1515.04, .c_kPa = 1.72, .phi_deg = 29.0, .K_m = kLoamK})},
      {.id = "clayey_soil",
       .product = "Clayey soil (Thailand, 38% moisture; Wong Table 2.3)",
       .source = "bekker_parameters.csv (Ding et al. 2015, Table I)",
       .figures = si({.n = 0.5, .k_c_kN = 13.19, .k_phi_kN = 692.15, .c_kPa = 4.14, .phi_deg = 13.0, .K_m = 0.006})},
      {.id = "lete_sand",
       .product = "LETE sand",
       .source = "bekker_parameters.csv (Project Chrono's SCM terrain preset)",
       .figures = si({.n = 0.793, .k_c_kN = 102.0, .k_phi_kN = 5301.0, .c_kPa = 1.3, .phi_deg = 31.1, .K_m = 0.012})},
      {.id = "lunar_soil",
       .product = "Lunar soil (Ding et al. 2015 Table I)",
       .source = "bekker_parameters.csv (Ding et al. 2015, Table I)",
       .figures = si({.n = 1.0, .k_c_kN = 1.4, .k_phi_kN = 820.0, .c_kPa = 0.17, .phi_deg = 35.0, .K_m = 0.018})},
      {.id = "hit_lss1",
       .product = "HIT-LSS1 lunar simulant",
       .source = "bekker_parameters.csv (Ding et al. 2015, Table I)",
       .figures = si({.n = 1.1, .k_c_kN = 15.6, .k_phi_kN = 2407.4, .c_kPa = 0.25, .phi_deg = 31.9, .K_m = 0.010})},
      {.id = "heavy_clay_25",
       .product = "Heavy clay (WES) 25% moisture",
       .source = kUnverifiedRowClayK,
       .figures = si({.n = 0.13, .k_c_kN = 12.70, .k_phi_kN = 1555.95, .c_kPa = 68.95, .phi_deg = 34.0, .K_m = kClayK})},
      {.id = "heavy_clay_40",
       .product = "Heavy clay (WES) 40% moisture",
       .source = kUnverifiedRowClayK,
       .figures = si({.n = 0.11, .k_c_kN = 1.84, .k_phi_kN = 103.27, .c_kPa = 20.69, .phi_deg = 6.0, .K_m = kClayK})},
      {.id = "lean_clay_22",
       .product = "Lean clay (WES) 22% moisture",
       .source = kUnverifiedRowClayK,
       .figures = si({.n = 0.2, .k_c_kN = 16.43, .k_phi_kN = 1724.69, .c_kPa = 68.95, .phi_deg = 20.0, .K_m = kClayK})},
      {.id = "lean_clay_32",
       .product = "Lean clay (WES) 32% moisture",
       .source = kUnverifiedRowClayK,
       .figures = si({.n = 0.15, .k_c_kN = 1.52, .k_phi_kN = 119.61, .c_kPa = 13.79, .phi_deg = 11.0, .K_m = kClayK})},
      {.id = "clayey_soil_55",
       .product = "Clayey soil (Thailand) 55% moisture",
       .source = kUnverifiedRowClayK,
       .figures = si({.n = 0.7, .k_c_kN = 16.03, .k_phi_kN = 1262.53, .c_kPa = 2.07, .phi_deg = 10.0, .K_m = kClayK})},
  };
  return presets;
}

}  // namespace hadal::physics

#include "hadal/physics/soil_presets.h"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "config/reference_csv_test_support.h"
#include "hadal/core/units.h"
#include "hadal/geometry/triangle_mesh.h"

namespace hadal::physics {
namespace {

using reference_tables::cell_figures;

// Rows of the reference tables by their `soil` column: n, k_c, k_phi, c_kPa, phi_deg, K_m, source as written.
std::map<std::string, std::vector<std::string>> reference_rows() {
  std::map<std::string, std::vector<std::string>> rows;
  for (const char* file : {"bekker_parameters.csv", "deep_sea_sediment.csv"}) {
    const auto table = reference_tables::csv_rows(std::string(HADAL_SOIL_REFERENCE_DIR) + "/" + file,
                                         "soil,n,k_c,k_phi,c_kPa,phi_deg,K_m,source", 8);
    rows.insert(table.begin(), table.end());
  }
  return rows;
}

// Every preset is its table row converted to SI (kN -> N, kPa -> Pa, deg -> rad), to the table's digits;
// K is the row's, or within its range, or -- where the row has none -- what the preset's source says.
TEST(SoilPresets, AreTheReferenceTablesRowsInSI) {
  const auto rows = reference_rows();
  ASSERT_EQ(soil_presets().size(), 12u);
  for (const config::Preset<SoilParameters>& preset : soil_presets()) {
    SCOPED_TRACE(std::string(preset.id));
    const auto row = rows.find(std::string(preset.product));
    ASSERT_NE(row, rows.end()) << "no row '" << preset.product << "'";
    const std::vector<std::string>& f = row->second;
    const SoilParameters& s = preset.figures;
    EXPECT_DOUBLE_EQ(s.sinkage_exponent, cell_figures(f[0]).at(0));
    EXPECT_NEAR(s.k_c, 1e3 * cell_figures(f[1]).at(0), 1e-9 * s.k_c);
    EXPECT_NEAR(s.k_phi, 1e3 * cell_figures(f[2]).at(0), 1e-9 * s.k_phi);
    EXPECT_NEAR(s.cohesion, 1e3 * cell_figures(f[3]).at(0), 1e-9 * s.cohesion);
    EXPECT_NEAR(s.friction_angle, cell_figures(f[4]).at(0) * kDegToRad, 1e-12);
    const std::vector<double> K = cell_figures(f[5]);
    if (K.size() == 1) {
      EXPECT_DOUBLE_EQ(s.shear_deformation_modulus, K[0]);
    } else if (K.size() == 2) {
      EXPECT_GE(s.shear_deformation_modulus, K[0]);
      EXPECT_LE(s.shear_deformation_modulus, K[1]);
      EXPECT_NE(preset.source.find("; K "), std::string::npos);  // says which K it takes
    } else {
      EXPECT_NE(preset.source.find("K assumed"), std::string::npos);
    }
    EXPECT_NO_THROW(SoilContact(geometry::TriangleMesh{}, s, 1.0, 0.002));
  }
}

TEST(SoilPresets, FoundById) {
  ASSERT_NE(config::find_preset(soil_presets(), "dry_sand"), nullptr);
  EXPECT_EQ(config::find_preset(soil_presets(), "dry_sand")->figures.sinkage_exponent, 1.1);
  EXPECT_NE(config::find_preset(soil_presets(), "deep_sea_ooze"), nullptr);
  EXPECT_EQ(config::find_preset(soil_presets(), "quicksand"), nullptr);
}

}  // namespace
}  // namespace hadal::physics

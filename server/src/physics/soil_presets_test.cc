#include "hadal/physics/soil_presets.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "hadal/core/units.h"
#include "hadal/geometry/triangle_mesh.h"

namespace hadal::physics {
namespace {

// The CSV's fields, quoted fields kept whole.
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

// Rows of the reference tables by their `soil` column: n, k_c, k_phi, c_kPa, phi_deg, K_m as written.
std::map<std::string, std::vector<std::string>> reference_rows() {
  std::map<std::string, std::vector<std::string>> rows;
  for (const char* file : {"bekker_parameters.csv", "deep_sea_sediment.csv"}) {
    std::ifstream in(std::string(HADAL_SOIL_REFERENCE_DIR) + "/" + file);
    EXPECT_TRUE(in) << file;
    std::string line;
    bool header = true;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (header) {
        EXPECT_EQ(line.rfind("soil,n,k_c,k_phi,c_kPa,phi_deg,K_m,source", 0), 0u) << file;
        header = false;
        continue;
      }
      std::vector<std::string> fields = split_csv(line);
      // One label in the published table holds an unquoted comma ("Clayey soil (Thailand, 38% ..."): the
      // row's 8 columns end with 7 figures and the source, so whatever comes before them is the label.
      while (fields.size() > 8) {
        fields[0] += "," + fields[1];
        fields.erase(fields.begin() + 1);
      }
      rows[fields[0]] = std::vector<std::string>(fields.begin() + 1, fields.end());
    }
  }
  return rows;
}

// A table figure: its leading number ("1.72 (unverified)" is 1.72); a range "0.010-0.025" gives both ends.
std::vector<double> figures(const std::string& text) {
  std::vector<double> out;
  std::istringstream in(text);
  double value = 0.0;
  if (in >> value) out.push_back(value);
  if (in.peek() == '-' && in.get() && in >> value) out.push_back(value);
  return out;
}

// Every preset is its table row converted to SI (kN -> N, kPa -> Pa, deg -> rad), to the table's digits;
// K is the row's, or within its range, or -- where the row has none -- what the preset's note says.
TEST(SoilPresets, AreTheReferenceTablesRowsInSI) {
  const auto rows = reference_rows();
  ASSERT_FALSE(soil_presets().empty());
  for (const SoilPreset& preset : soil_presets()) {
    SCOPED_TRACE(preset.name);
    const auto row = rows.find(preset.table_row);
    ASSERT_NE(row, rows.end()) << "no row '" << preset.table_row << "'";
    const std::vector<std::string>& f = row->second;
    const SoilParameters& s = preset.soil;
    EXPECT_DOUBLE_EQ(s.sinkage_exponent, figures(f[0]).at(0));
    EXPECT_NEAR(s.k_c, 1e3 * figures(f[1]).at(0), 1e-9 * s.k_c);
    EXPECT_NEAR(s.k_phi, 1e3 * figures(f[2]).at(0), 1e-9 * s.k_phi);
    EXPECT_NEAR(s.cohesion, 1e3 * figures(f[3]).at(0), 1e-9 * s.cohesion);
    EXPECT_NEAR(s.friction_angle, figures(f[4]).at(0) * kDegToRad, 1e-12);
    const std::vector<double> K = figures(f[5]);
    if (K.size() == 1) {
      EXPECT_DOUBLE_EQ(s.shear_deformation_modulus, K[0]);
    } else if (K.size() == 2) {
      EXPECT_GE(s.shear_deformation_modulus, K[0]);
      EXPECT_LE(s.shear_deformation_modulus, K[1]);
      EXPECT_FALSE(preset.note.empty());
    } else {
      EXPECT_NE(preset.note.find("K assumed"), std::string::npos);
    }
    EXPECT_NO_THROW(SoilContact(geometry::TriangleMesh{}, s, 1.0, 0.002));
  }
}

TEST(SoilPresets, FoundByName) {
  ASSERT_NE(find_soil_preset("dry_sand"), nullptr);
  EXPECT_EQ(find_soil_preset("dry_sand")->soil.sinkage_exponent, 1.1);
  EXPECT_NE(find_soil_preset("deep_sea_ooze"), nullptr);
  EXPECT_EQ(find_soil_preset("quicksand"), nullptr);
  EXPECT_NE(soil_preset_names().find("dry_sand, sandy_loam"), std::string::npos);
}

}  // namespace
}  // namespace hadal::physics

// The presets against the published tables they come from (docs/reference/optics/), recomputed here.
#include "hadal/render/water_presets.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace hadal::render {
namespace {

using Spectrum = std::vector<std::pair<double, double>>;  // (wavelength [nm], value)

// Column `name` of a CSV with '#' comment lines, a header row and wavelength_nm first.
Spectrum csv_column(const std::string& file, const std::string& name) {
  std::ifstream in(std::string(HADAL_OPTICS_REFERENCE_DIR) + "/" + file);
  EXPECT_TRUE(in.good()) << file;
  std::string line;
  std::vector<std::string> header;
  Spectrum spectrum;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    for (std::size_t c = 1; c < header.size(); ++c) {
      if (header[c] == name) spectrum.emplace_back(std::stod(cells[0]), std::stod(cells[c]));
    }
  }
  return spectrum;
}

Spectrum pope_fry() {
  std::ifstream in(std::string(HADAL_OPTICS_REFERENCE_DIR) + "/pope_fry_1997_pure_water_absorption.txt");
  EXPECT_TRUE(in.good());
  Spectrum spectrum;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("lambda", 0) == 0) continue;
    std::stringstream cells(line);
    double wavelength = 0.0, value = 0.0;
    cells >> wavelength >> value;
    spectrum.emplace_back(wavelength, value);
  }
  return spectrum;
}

// Trapezoid mean over [lo, hi] of the tabulated points inside it (the bands start and end on rows).
double band_mean(const Spectrum& s, double lo, double hi) {
  double area = 0.0;
  for (std::size_t i = 1; i < s.size(); ++i) {
    if (s[i - 1].first >= lo && s[i].first <= hi) area += (s[i].first - s[i - 1].first) * 0.5 * (s[i - 1].second + s[i].second);
  }
  return area / (hi - lo);
}

Rgb bands(const Spectrum& s) { return Rgb(band_mean(s, 600, 700), band_mean(s, 500, 600), band_mean(s, 400, 500)); }

// The coded values carry 6 significant digits: relative tolerance 1e-5.
void expect_close(const Rgb& coded, const Rgb& table, const std::string& what) {
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(coded[ch] / table[ch], 1.0, 1e-5) << what << " channel " << ch;
}

TEST(WaterPresetsTest, JerlovKdAreTheTablesBandMeans) {
  const std::pair<JerlovType, const char*> austin_petzold[] = {{JerlovType::kI, "I"},   {JerlovType::kIA, "IA"},
                                                              {JerlovType::kIB, "IB"}, {JerlovType::kII, "II"},
                                                              {JerlovType::kIII, "III"}, {JerlovType::k1C, "C1"}};
  for (const auto& [type, column] : austin_petzold) {
    const Spectrum s = csv_column("austin_petzold1984_jerlov_update_Kd.csv", column);
    ASSERT_EQ(s.size(), 13u) << column;
    expect_close(jerlov_Kd_per_m(type), bands(s), column);
  }
  const std::pair<JerlovType, const char*> jerlov[] = {
      {JerlovType::k3C, "C3"}, {JerlovType::k5C, "C5"}, {JerlovType::k7C, "C7"}, {JerlovType::k9C, "C9"}};
  for (const auto& [type, column] : jerlov) {
    const Spectrum s = csv_column("jerlov1976_tableXXVII_Kd.csv", column);
    ASSERT_EQ(s.size(), 15u) << column;
    expect_close(jerlov_Kd_per_m(type), bands(s), column);
  }
  // Clearer water lets blue deepest; red is absorbed by the water itself in every type.
  EXPECT_LT(jerlov_Kd_per_m(JerlovType::kI)[2], jerlov_Kd_per_m(JerlovType::kI)[1]);
  EXPECT_GT(jerlov_Kd_per_m(JerlovType::kI)[0], pure_water_absorption_per_m()[0]);
}

TEST(WaterPresetsTest, PureWaterAbsorptionIsPopeAndFrysBandMeans) {
  expect_close(pure_water_absorption_per_m(), bands(pope_fry()), "Pope & Fry");
}

TEST(WaterPresetsTest, Names) {
  for (const char* name : {"I", "IA", "IB", "II", "III", "1C", "3C", "5C", "7C", "9C"}) {
    JerlovType type{};
    ASSERT_TRUE(jerlov_type_from_string(name, &type)) << name;
    EXPECT_EQ(to_string(type), name);
  }
  JerlovType unused{};
  EXPECT_FALSE(jerlov_type_from_string("IV", &unused));
}

}  // namespace
}  // namespace hadal::render

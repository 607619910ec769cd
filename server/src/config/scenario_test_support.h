// What the scenario-loading tests share (the loader's, and each subsystem's key tests beside its code):
// a fixture that writes files into a temporary directory and loads them, and a valid inline vehicle.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "hadal/config/scenario_loader.h"
#include "hadal/physics/actuator_kinds.h"  // spec_of<Kind>
#include "hadal/sensors/sensor_kinds.h"

namespace hadal::config {

using Lines = std::vector<std::string>;

// Tolerance for values that went through a few floating-point operations (deg -> rad, normalisation).
constexpr double kTol = 1e-12;

// Each test writes its files into its own temporary directory, removed afterwards.
class ScenarioLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        std::filesystem::temp_directory_path() / ("hadal_config_test_" + std::to_string(::getpid()) + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Writes `text` to dir/relative and returns that path.
  std::string write(const std::string& relative, const std::string& text) {
    const std::filesystem::path path = dir_ / relative;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path.string();
  }

  // The formatted diagnostics of loading `path`; the model must be set exactly when there are none.
  static std::vector<std::string> errors_of(const std::string& path) {
    const LoadResult result = load_scenario_file(path);
    EXPECT_EQ(result.model.has_value(), result.errors.empty());
    std::vector<std::string> lines;
    for (const Diagnostic& diagnostic : result.errors) lines.push_back(diagnostic.format());
    return lines;
  }

  std::filesystem::path dir_;
};

// A valid vehicle entry with an inline definition and one thruster. It starts with a newline, so after
// "vehicles:" on line N its "- name: auv" is line N + 1 and its last line ("max_rpm") is N + 14; tests
// append keys after it or place broken entries around it.
constexpr const char* kInlineVehicle = R"(
  - name: auv
    type: auv
    links:
      - name: hull
        mass: 30.0
        inertia: {ixx: 0.09, iyy: 6.4, izz: 6.4}
    thrusters:
      - name: main
        link: hull
        position: [-0.8, 0, 0]
        direction: [2, 0, 0]
        propeller_diameter: 0.1
        thrust_coefficient: 0.4
        max_rpm: 1500
)";

// A vehicle entry with one link and a `sensors:` key, for the sensors' entries to follow.
constexpr const char* kSensorVehicle = R"(vehicles:
  - name: auv
    type: auv
    links:
      - {name: hull, mass: 30.0, inertia: {ixx: 1, iyy: 1, izz: 1}}
    sensors:
)";

}  // namespace hadal::config

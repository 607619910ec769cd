#include "plot.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace hadal::validation::plot {
namespace {

// Tick values are k * step computed in double: compare with a relative tolerance of a few ulps.
void expect_values(const std::vector<double>& actual, const std::vector<double>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i) {
    EXPECT_NEAR(actual[i], expected[i], 1e-12 * std::max(1.0, std::fabs(expected[i]))) << i;
  }
}

TEST(NiceNumber, RoundsToOneTwoFiveTimesPowersOfTen) {
  EXPECT_DOUBLE_EQ(nice_number(0.13, true), 0.1);
  EXPECT_DOUBLE_EQ(nice_number(0.27, true), 0.2);
  EXPECT_DOUBLE_EQ(nice_number(3.4, true), 5.0);
  EXPECT_DOUBLE_EQ(nice_number(8.0, true), 10.0);
  EXPECT_DOUBLE_EQ(nice_number(3.4, false), 5.0);  // ceiling
  EXPECT_DOUBLE_EQ(nice_number(5.1, false), 10.0);
  EXPECT_DOUBLE_EQ(nice_number(2000.0, false), 2000.0);
}

TEST(NiceTicks, UnitInterval) {
  const Ticks t = nice_ticks(0.0, 1.0, 6);
  EXPECT_DOUBLE_EQ(t.step, 0.2);
  expect_values(t.values, {0.0, 0.2, 0.4, 0.6, 0.8, 1.0});
}

TEST(NiceTicks, OffsetNegativeInterval) {
  // Range 15.8 -> nice 20, 20 / 5 = 4 -> step 5; ticks inside [-3.7, 12.1].
  const Ticks t = nice_ticks(-3.7, 12.1, 6);
  EXPECT_DOUBLE_EQ(t.step, 5.0);
  expect_values(t.values, {0.0, 5.0, 10.0});
}

TEST(NiceTicks, LargeValuesAndExactZero) {
  const Ticks t = nice_ticks(-3000.0, 0.0, 5);
  EXPECT_DOUBLE_EQ(t.step, 1000.0);
  expect_values(t.values, {-3000.0, -2000.0, -1000.0, 0.0});
  const Ticks u = nice_ticks(-0.3, 0.3, 7);  // 0 must be exactly 0, not 5.5e-17
  for (double v : u.values) {
    if (std::fabs(v) < 1e-3) {
      EXPECT_EQ(v, 0.0);
    }
  }
}

TEST(NiceTicks, DegenerateIntervalIsWidened) {
  const Ticks t = nice_ticks(5.0, 5.0, 5);
  ASSERT_FALSE(t.values.empty());
  EXPECT_LE(t.values.front(), 5.0);
  EXPECT_GE(t.values.back(), 5.0);
}

TEST(LogTicks, DecadesAndMinors) {
  expect_values(log_major_ticks(0.003, 200.0), {0.01, 0.1, 1.0, 10.0, 100.0});
  expect_values(log_major_ticks(1.0, 1000.0), {1.0, 10.0, 100.0, 1000.0});
  expect_values(log_minor_ticks(1.0, 30.0), {2, 3, 4, 5, 6, 7, 8, 9, 20, 30});
  EXPECT_TRUE(log_major_ticks(-1.0, 10.0).empty());
}

TEST(AxisRange, LinearWidensToTicksLogToDecades) {
  const std::vector<double> data = {0.3, 9.2};
  Axis linear;
  const Range r = axis_range(linear, {&data});
  EXPECT_DOUBLE_EQ(r.lo, 0.0);
  EXPECT_DOUBLE_EQ(r.hi, 10.0);
  Axis log;
  log.scale = Scale::kLog10;
  const std::vector<double> positive = {0.02, -5.0, 300.0};  // -5 is skipped on a log axis
  const Range l = axis_range(log, {&positive});
  EXPECT_DOUBLE_EQ(l.lo, 0.01);
  EXPECT_DOUBLE_EQ(l.hi, 1000.0);
  Axis fixed;
  fixed.min = -1.0;
  fixed.max = 2.5;
  const Range f = axis_range(fixed, {&data});
  EXPECT_DOUBLE_EQ(f.lo, -1.0);
  EXPECT_DOUBLE_EQ(f.hi, 2.5);
}

TEST(FormatTick, DecimalsFollowTheStep) {
  EXPECT_EQ(format_tick(0.4, 0.2), "0.4");
  EXPECT_EQ(format_tick(-2000.0, 1000.0), "-2000");
  EXPECT_EQ(format_tick(0.05, 0.01), "0.05");
  EXPECT_EQ(format_tick(1e-17, 0.1), "0");
  EXPECT_EQ(format_tick(2.5e6, 5e5), "2.5e+06");
}

// Counts pixels that are not white inside `rect`.
int ink(const cv::Mat& image, const cv::Rect& rect) {
  int count = 0;
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    for (int x = rect.x; x < rect.x + rect.width; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      if (p[0] != 255 || p[1] != 255 || p[2] != 255) ++count;
    }
  }
  return count;
}

TEST(Render, WritesPngOfTheExpectedSizeWithInkInThePlotAreas) {
  Figure figure;
  figure.title = "plot_test";
  figure.panel_width = 400;
  figure.panel_height = 300;
  Panel linear;
  linear.title = "linear";
  linear.x.label = "distance [m]";
  linear.y.label = "deviation [m]";
  Series a;
  a.label = "sine";
  Series b;
  b.label = "dashed";
  b.dashed = true;
  b.color = palette(1);
  for (int i = 0; i <= 100; ++i) {
    a.x.push_back(i);
    a.y.push_back(std::sin(0.1 * i));
    b.x.push_back(i);
    b.y.push_back(0.5);
  }
  linear.series = {a, b};
  Panel loglog;
  loglog.title = "log-log";
  loglog.x.scale = loglog.y.scale = Scale::kLog10;
  loglog.x.label = "tau [s]";
  loglog.y.label = "sigma [m/s^2]";
  Series c;
  c.label = "slope -1/2";
  c.marker = Marker::kCircle;
  for (int i = 0; i <= 40; ++i) {
    const double tau = std::pow(10.0, -1.0 + 0.1 * i);
    c.x.push_back(tau);
    c.y.push_back(1e-3 / std::sqrt(tau));
  }
  loglog.series = {c};
  loglog.legend = LegendPosition::kBottomLeft;
  figure.panels = {linear, loglog};

  const std::string path = ::testing::TempDir() + "hadal_plot_test.png";
  std::remove(path.c_str());
  ASSERT_EQ(write_png(figure, path), "");
  const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.cols, 800);
  EXPECT_GT(image.rows, 300);  // panel height plus the title row
  const int title = image.rows - 300;
  // The central part of each panel's plot area carries curves (and grid lines).
  EXPECT_GT(ink(image, cv::Rect(150, title + 80, 150, 120)), 100);
  EXPECT_GT(ink(image, cv::Rect(550, title + 80, 150, 120)), 100);
  // Coloured pixels exist (the series, not just black frame and grey grid).
  int coloured = 0;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      if (std::abs(p[0] - p[2]) > 60) ++coloured;
    }
  }
  EXPECT_GT(coloured, 200);
  std::remove(path.c_str());
}

TEST(Render, EmptyPanelAndBadPath) {
  Figure figure;
  figure.panels.resize(1);  // no series: axes from defaults, nothing drawn, no crash
  const cv::Mat image = render(figure);
  EXPECT_EQ(image.cols, 640);
  EXPECT_EQ(image.rows, 480);
  EXPECT_NE(write_png(figure, "/nonexistent-dir/x.png"), "");
}

}  // namespace
}  // namespace hadal::validation::plot

// Minimal line plots on OpenCV (cv::Mat drawing, PNG via cv::imwrite) for the validation figures: no
// plotting dependency beyond what Hadal already links.
//
// A Figure is one or more Panels side by side (one row), each panel_width x panel_height pixels,
// under an optional figure title. A Panel has a title, two Axes and Series of (x, y) points drawn as
// anti-aliased polylines (solid or dashed, optional markers), a legend box and tick labels at "nice"
// numbers (1, 2, 5 x 10^k steps, Heckbert 1990).
//
// Axes: linear, or log10 (ticks at decades labelled 10^k, minor ticks at 2..9 x 10^k; when the range
// spans less than a decade, nice linear ticks inside it). Limits are automatic from the finite data
// (linear: widened to the enclosing ticks; log: to whole decades, or a small margin within a decade)
// unless Axis::min/max are set. On a log axis non-positive values are skipped. A NaN or Inf
// point breaks a polyline (gaps in the data). `equal_aspect` widens one axis so one data unit has the
// same length in x and y (tracks in a plane); linear axes only.
//
// Coordinates: pixel (0, 0) is the image's top-left; data y grows upwards.
#pragma once

#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace hadal::validation::plot {

struct Color {
  std::uint8_t r = 0, g = 0, b = 0;
  cv::Scalar bgr() const { return cv::Scalar(b, g, r); }
};

// A colour-blind-safe cycle (Okabe & Ito 2008): blue, vermillion, bluish green, orange, sky blue,
// reddish purple, yellow, black.
Color palette(int index);

enum class Scale { kLinear, kLog10 };

struct Axis {
  std::string label;  // with the unit, e.g. "depth [m]"
  Scale scale = Scale::kLinear;
  std::optional<double> min, max;  // fixed limits (data units); automatic when empty
};

enum class Marker { kNone, kCircle, kSquare };

struct Series {
  std::string label;  // legend entry; empty: not in the legend
  std::vector<double> x, y;
  Color color = palette(0);
  double line_width = 2.0;  // [px]; 0 draws markers only
  bool dashed = false;
  Marker marker = Marker::kNone;
  int marker_size = 4;  // radius / half side [px]
};

enum class LegendPosition { kNone, kTopLeft, kTopRight, kBottomLeft, kBottomRight };

struct Panel {
  std::string title;
  Axis x, y;
  std::vector<Series> series;
  LegendPosition legend = LegendPosition::kTopRight;
  bool grid = true;
  bool equal_aspect = false;
};

struct Figure {
  std::string title;  // above all panels; empty: no title row
  int panel_width = 640;
  int panel_height = 480;
  std::vector<Panel> panels;
};

// Tick values for the interval [lo, hi]: multiples of a nice step (1, 2 or 5 x 10^k) chosen so that
// about `target` ticks fall inside; returns the ticks within [lo, hi] (up to rounding) and the step.
struct Ticks {
  std::vector<double> values;
  double step = 0.0;
};
Ticks nice_ticks(double lo, double hi, int target = 6);
// The nice number closest to x > 0 (round) or the smallest nice number >= x (!round), nice being
// 1, 2, 5 or 10 times a power of ten (Heckbert, "Nice numbers for graph labels", Graphics Gems 1990).
double nice_number(double x, bool round);
// Decades 10^k within [lo, hi] (lo > 0), and minor ticks m 10^k, m = 2..9, within [lo, hi].
std::vector<double> log_major_ticks(double lo, double hi);
std::vector<double> log_minor_ticks(double lo, double hi);
// Tick label for `value` on a linear axis with tick spacing `step`: as many decimals as the step
// needs; scientific (1.5e+06) for very large or very small magnitudes; "0" for |value| < step/1e6.
std::string format_tick(double value, double step);

// Data limits an axis uses for `values` (ticks for linear auto limits), before equal_aspect.
struct Range {
  double lo = 0.0, hi = 1.0;
};
Range axis_range(const Axis& axis, const std::vector<const std::vector<double>*>& values);

// Renders the figure (BGR, 8 bit, white background).
cv::Mat render(const Figure& figure);
// Renders and writes a PNG. Returns "" on success, otherwise an error message naming the file.
std::string write_png(const Figure& figure, const std::string& path);

}  // namespace hadal::validation::plot

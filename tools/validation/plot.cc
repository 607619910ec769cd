#include "plot.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace hadal::validation::plot {

namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTickFont = 0.45;
constexpr double kLabelFont = 0.55;
constexpr double kTitleFont = 0.65;
constexpr double kFigureTitleFont = 0.75;
constexpr double kExponentFont = 0.35;
constexpr int kTickLength = 6;                // [px]
constexpr int kShift = 4;                     // cv::line fixed-point bits: 1/16 px
constexpr double kDashOn = 10.0, kDashOff = 6.0;  // [px]
const cv::Scalar kBlack(0, 0, 0);
const cv::Scalar kWhite(255, 255, 255);
const cv::Scalar kGrid(225, 225, 225);
const cv::Scalar kMinorGrid(242, 242, 242);

cv::Size text_size(const std::string& text, double scale, int thickness = 1) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, thickness, &baseline);
}

// Text with its top-left corner at `top_left` (putText anchors at the baseline's left end).
void put_text(cv::Mat& image, const std::string& text, cv::Point top_left, double scale,
              int thickness = 1, const cv::Scalar& color = kBlack) {
  const cv::Size size = text_size(text, scale, thickness);
  cv::putText(image, text, cv::Point(top_left.x, top_left.y + size.height), kFont, scale, color,
              thickness, cv::LINE_AA);
}

// Text rotated by 90 degrees counter-clockwise (reading bottom to top), centred at `center`.
void put_vertical_text(cv::Mat& image, const std::string& text, cv::Point center, double scale) {
  if (text.empty()) return;
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, kFont, scale, 1, &baseline);
  cv::Mat block(size.height + baseline + 2, size.width + 2, image.type(), kWhite);
  cv::putText(block, text, cv::Point(1, size.height + 1), kFont, scale, kBlack, 1, cv::LINE_AA);
  cv::Mat rotated;
  cv::rotate(block, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
  cv::Rect target(center.x - rotated.cols / 2, center.y - rotated.rows / 2, rotated.cols,
                  rotated.rows);
  const cv::Rect clipped = target & cv::Rect(0, 0, image.cols, image.rows);
  if (clipped.empty()) return;
  rotated(cv::Rect(clipped.x - target.x, clipped.y - target.y, clipped.width, clipped.height))
      .copyTo(image(clipped));
}

// A label "10^k" drawn as "10" with a raised smaller exponent; returns its size.
cv::Size power_label_size(int k) {
  const cv::Size base = text_size("10", kTickFont);
  const cv::Size exponent = text_size(std::to_string(k), kExponentFont);
  return cv::Size(base.width + exponent.width + 1, base.height + exponent.height / 2);
}
void put_power_label(cv::Mat& image, int k, cv::Point top_left) {
  const cv::Size exponent = text_size(std::to_string(k), kExponentFont);
  const cv::Size base = text_size("10", kTickFont);
  put_text(image, "10", cv::Point(top_left.x, top_left.y + exponent.height / 2), kTickFont);
  put_text(image, std::to_string(k), cv::Point(top_left.x + base.width + 1, top_left.y),
           kExponentFont);
}

bool usable(double v, Scale scale) {
  return std::isfinite(v) && (scale == Scale::kLinear || v > 0.0);
}

double to_axis(double v, Scale scale) { return scale == Scale::kLog10 ? std::log10(v) : v; }

// One axis after limits are fixed: transformed range [a, b] (log10 units on a log axis).
struct AxisMap {
  Scale scale = Scale::kLinear;
  double a = 0.0, b = 1.0;
  double lo() const { return scale == Scale::kLog10 ? std::pow(10.0, a) : a; }
  double hi() const { return scale == Scale::kLog10 ? std::pow(10.0, b) : b; }
  // Fraction along the axis, 0 at a and 1 at b.
  double fraction(double v) const { return (to_axis(v, scale) - a) / (b - a); }
};

// Tick marks and labels of one axis.
struct TickMark {
  double value = 0.0;
  bool major = true;
  std::string label;   // empty for minor ticks and power labels
  bool power = false;  // label 10^exponent instead
  int exponent = 0;
};

std::vector<TickMark> axis_ticks(const AxisMap& map) {
  std::vector<TickMark> marks;
  const double lo = map.lo(), hi = map.hi();
  if (map.scale == Scale::kLog10) {
    const std::vector<double> majors = log_major_ticks(lo, hi);
    if (majors.size() >= 2) {
      for (double v : majors) {
        TickMark m;
        m.value = v;
        m.power = true;
        m.exponent = static_cast<int>(std::lround(std::log10(v)));
        marks.push_back(m);
      }
      for (double v : log_minor_ticks(lo, hi)) marks.push_back({v, false, "", false, 0});
      return marks;
    }
    // Less than a decade: nice linear values inside the range.
    const Ticks ticks = nice_ticks(lo, hi, 5);
    for (double v : ticks.values) {
      if (v > 0.0) marks.push_back({v, true, format_tick(v, ticks.step), false, 0});
    }
    return marks;
  }
  const Ticks ticks = nice_ticks(lo, hi, 6);
  for (double v : ticks.values) marks.push_back({v, true, format_tick(v, ticks.step), false, 0});
  return marks;
}

cv::Size tick_label_size(const TickMark& mark) {
  return mark.power ? power_label_size(mark.exponent) : text_size(mark.label, kTickFont);
}
void put_tick_label(cv::Mat& image, const TickMark& mark, cv::Point top_left) {
  if (mark.power) {
    put_power_label(image, mark.exponent, top_left);
  } else {
    put_text(image, mark.label, top_left, kTickFont);
  }
}

// Liang-Barsky clip of the segment p0-p1 to the rectangle [x0, x1] x [y0, y1]; false if outside.
bool clip_segment(cv::Point2d& p0, cv::Point2d& p1, double x0, double y0, double x1, double y1) {
  double t0 = 0.0, t1 = 1.0;
  const double dx = p1.x - p0.x, dy = p1.y - p0.y;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {p0.x - x0, x1 - p0.x, p0.y - y0, y1 - p0.y};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  const cv::Point2d a = p0;
  p0 = a + t0 * cv::Point2d(dx, dy);
  p1 = a + t1 * cv::Point2d(dx, dy);
  return true;
}

cv::Point fixed_point(const cv::Point2d& p) {
  return cv::Point(static_cast<int>(std::lround(p.x * (1 << kShift))),
                   static_cast<int>(std::lround(p.y * (1 << kShift))));
}

void draw_segment(cv::Mat& roi, cv::Point2d a, cv::Point2d b, const cv::Scalar& color,
                  int thickness) {
  // Clip a few pixels outside the region so line caps at the border are drawn by OpenCV's own
  // clipping, and coordinates stay far from int overflow.
  const double m = 4.0 + thickness;
  if (!clip_segment(a, b, -m, -m, roi.cols - 1 + m, roi.rows - 1 + m)) return;
  cv::line(roi, fixed_point(a), fixed_point(b), color, thickness, cv::LINE_AA, kShift);
}

// Polyline through `points` (a NaN point breaks it), dashed or solid.
void draw_polyline(cv::Mat& roi, const std::vector<cv::Point2d>& points, const Series& s) {
  const int thickness = std::max(1, static_cast<int>(std::lround(s.line_width)));
  double phase = 0.0;  // distance along the dash pattern [px]
  for (std::size_t i = 1; i < points.size(); ++i) {
    const cv::Point2d a = points[i - 1], b = points[i];
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y)) {
      phase = 0.0;
      continue;
    }
    if (!s.dashed) {
      draw_segment(roi, a, b, s.color.bgr(), thickness);
      continue;
    }
    const double length = cv::norm(b - a);
    double t = 0.0;
    while (t < length) {
      const double period = kDashOn + kDashOff;
      const double in_period = std::fmod(phase, period);
      const bool on = in_period < kDashOn;
      const double run = std::min(length - t, (on ? kDashOn : period) - in_period);
      if (on && length > 0.0) {
        draw_segment(roi, a + (b - a) * (t / length), a + (b - a) * ((t + run) / length),
                     s.color.bgr(), thickness);
      }
      t += run;
      phase += run;
    }
  }
}

void draw_marker(cv::Mat& roi, const cv::Point2d& p, const Series& s) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y)) return;
  if (p.x < -50 || p.y < -50 || p.x > roi.cols + 50 || p.y > roi.rows + 50) return;
  const int r = s.marker_size;
  if (s.marker == Marker::kCircle) {
    cv::circle(roi, fixed_point(p), r << kShift, s.color.bgr(), cv::FILLED, cv::LINE_AA, kShift);
  } else if (s.marker == Marker::kSquare) {
    cv::rectangle(roi, fixed_point(p - cv::Point2d(r, r)), fixed_point(p + cv::Point2d(r, r)),
                  s.color.bgr(), cv::FILLED, cv::LINE_AA, kShift);
  }
}

void draw_legend(cv::Mat& image, const cv::Rect& area, const Panel& panel) {
  std::vector<const Series*> entries;
  for (const Series& s : panel.series) {
    if (!s.label.empty()) entries.push_back(&s);
  }
  if (entries.empty() || panel.legend == LegendPosition::kNone) return;
  constexpr int kSample = 34, kPad = 8, kRow = 20;
  int text_width = 0;
  for (const Series* s : entries) text_width = std::max(text_width, text_size(s->label, kTickFont).width);
  const int width = kPad + kSample + 6 + text_width + kPad;
  const int height = kPad + kRow * static_cast<int>(entries.size()) + kPad / 2;
  const bool left = panel.legend == LegendPosition::kTopLeft || panel.legend == LegendPosition::kBottomLeft;
  const bool top = panel.legend == LegendPosition::kTopLeft || panel.legend == LegendPosition::kTopRight;
  const cv::Rect box(left ? area.x + 10 : area.x + area.width - width - 10,
                     top ? area.y + 10 : area.y + area.height - height - 10, width, height);
  cv::rectangle(image, box, kWhite, cv::FILLED);
  cv::rectangle(image, box, cv::Scalar(160, 160, 160), 1);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const Series& s = *entries[k];
    const int y = box.y + kPad + kRow * static_cast<int>(k) + kRow / 2;
    cv::Mat roi = image(cv::Rect(box.x + kPad, y - kRow / 2, kSample, kRow));
    if (s.line_width > 0.0) {
      draw_polyline(roi, {cv::Point2d(0, kRow / 2.0), cv::Point2d(kSample - 1, kRow / 2.0)}, s);
    }
    if (s.marker != Marker::kNone) draw_marker(roi, cv::Point2d(kSample / 2.0, kRow / 2.0), s);
    const cv::Size size = text_size(s.label, kTickFont);
    put_text(image, s.label, cv::Point(box.x + kPad + kSample + 6, y - size.height / 2), kTickFont);
  }
}

AxisMap make_map(const Axis& axis, const std::vector<const std::vector<double>*>& values) {
  const Range r = axis_range(axis, values);
  AxisMap map;
  map.scale = axis.scale;
  map.a = to_axis(r.lo, axis.scale);
  map.b = to_axis(r.hi, axis.scale);
  if (!(map.b > map.a)) map.b = map.a + 1.0;
  return map;
}

void draw_panel(cv::Mat& image, const cv::Rect& rect, const Panel& panel) {
  std::vector<const std::vector<double>*> xs, ys;
  for (const Series& s : panel.series) {
    xs.push_back(&s.x);
    ys.push_back(&s.y);
  }
  AxisMap mx = make_map(panel.x, xs);
  AxisMap my = make_map(panel.y, ys);

  // Margins: left from the widest y tick label (fixed point: the labels depend on the range).
  const int title_height = panel.title.empty() ? 10 : text_size(panel.title, kTitleFont).height + 22;
  const int label_height = text_size("Ay", kLabelFont).height + 6;
  const int bottom = kTickLength + text_size("0", kTickFont).height + 10 +
                     (panel.x.label.empty() ? 0 : label_height + 8);
  auto left_margin = [&](const AxisMap& y_map) {
    int widest = 0;
    for (const TickMark& m : axis_ticks(y_map)) {
      if (m.major) widest = std::max(widest, tick_label_size(m).width);
    }
    return 10 + (panel.y.label.empty() ? 0 : label_height + 6) + widest + 6 + kTickLength;
  };
  int left = left_margin(my);
  const int right = 22;
  cv::Rect area(rect.x + left, rect.y + title_height, rect.width - left - right,
                rect.height - title_height - bottom);

  if (panel.equal_aspect && mx.scale == Scale::kLinear && my.scale == Scale::kLinear) {
    // Same data units per pixel along x and y: widen the axis that has fewer.
    for (int pass = 0; pass < 2; ++pass) {
      const double ux = (mx.b - mx.a) / area.width, uy = (my.b - my.a) / area.height;
      if (ux > uy) {
        const double c = 0.5 * (my.a + my.b), half = 0.5 * ux * area.height;
        if (!panel.y.min && !panel.y.max) my.a = c - half, my.b = c + half;
      } else {
        const double c = 0.5 * (mx.a + mx.b), half = 0.5 * uy * area.width;
        if (!panel.x.min && !panel.x.max) mx.a = c - half, mx.b = c + half;
      }
      left = left_margin(my);  // y labels may have changed
      area = cv::Rect(rect.x + left, rect.y + title_height, rect.width - left - right,
                      rect.height - title_height - bottom);
    }
  }
  if (area.width < 10 || area.height < 10) return;

  auto px = [&](double x) { return mx.fraction(x) * (area.width - 1); };
  auto py = [&](double y) { return (1.0 - my.fraction(y)) * (area.height - 1); };

  const std::vector<TickMark> x_ticks = axis_ticks(mx), y_ticks = axis_ticks(my);
  cv::Mat roi = image(area);
  if (panel.grid) {
    for (const TickMark& m : x_ticks) {
      const int x = static_cast<int>(std::lround(px(m.value)));
      cv::line(roi, cv::Point(x, 0), cv::Point(x, area.height - 1), m.major ? kGrid : kMinorGrid, 1);
    }
    for (const TickMark& m : y_ticks) {
      const int y = static_cast<int>(std::lround(py(m.value)));
      cv::line(roi, cv::Point(0, y), cv::Point(area.width - 1, y), m.major ? kGrid : kMinorGrid, 1);
    }
  }

  for (const Series& s : panel.series) {
    std::vector<cv::Point2d> points;
    const std::size_t n = std::min(s.x.size(), s.y.size());
    points.reserve(n);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 0; i < n; ++i) {
      if (usable(s.x[i], mx.scale) && usable(s.y[i], my.scale)) {
        points.emplace_back(px(s.x[i]), py(s.y[i]));
      } else {
        points.emplace_back(nan, nan);
      }
    }
    if (s.line_width > 0.0) draw_polyline(roi, points, s);
    if (s.marker != Marker::kNone) {
      for (const cv::Point2d& p : points) draw_marker(roi, p, s);
    }
  }

  // Frame, ticks and tick labels.
  cv::rectangle(image, area, kBlack, 1);
  for (const TickMark& m : x_ticks) {
    const int x = area.x + static_cast<int>(std::lround(px(m.value)));
    const int length = m.major ? kTickLength : kTickLength / 2;
    cv::line(image, cv::Point(x, area.y + area.height - 1), cv::Point(x, area.y + area.height - 1 + length),
             kBlack, 1);
    if (!m.major) continue;
    const cv::Size size = tick_label_size(m);
    put_tick_label(image, m, cv::Point(x - size.width / 2, area.y + area.height + kTickLength + 4));
  }
  for (const TickMark& m : y_ticks) {
    const int y = area.y + static_cast<int>(std::lround(py(m.value)));
    const int length = m.major ? kTickLength : kTickLength / 2;
    cv::line(image, cv::Point(area.x - length, y), cv::Point(area.x, y), kBlack, 1);
    if (!m.major) continue;
    const cv::Size size = tick_label_size(m);
    put_tick_label(image, m, cv::Point(area.x - kTickLength - 4 - size.width, y - size.height / 2));
  }

  // Axis labels and title.
  if (!panel.x.label.empty()) {
    const cv::Size size = text_size(panel.x.label, kLabelFont);
    put_text(image, panel.x.label,
             cv::Point(area.x + area.width / 2 - size.width / 2, rect.y + rect.height - label_height - 4),
             kLabelFont);
  }
  if (!panel.y.label.empty()) {
    put_vertical_text(image, panel.y.label, cv::Point(rect.x + 10 + label_height / 2, area.y + area.height / 2),
                      kLabelFont);
  }
  if (!panel.title.empty()) {
    // Centred over the plot area, but kept inside the panel when it is wider than the area.
    const cv::Size size = text_size(panel.title, kTitleFont);
    const int x = std::clamp(area.x + area.width / 2 - size.width / 2, rect.x + 4,
                             std::max(rect.x + 4, rect.x + rect.width - size.width - 4));
    put_text(image, panel.title, cv::Point(x, rect.y + 10), kTitleFont);
  }
  draw_legend(image, area, panel);
}

}  // namespace

Color palette(int index) {
  static const Color kColors[] = {{0, 114, 178},  {213, 94, 0},   {0, 158, 115}, {230, 159, 0},
                                  {86, 180, 233}, {204, 121, 167}, {240, 228, 66}, {0, 0, 0}};
  const int n = static_cast<int>(sizeof(kColors) / sizeof(kColors[0]));
  return kColors[((index % n) + n) % n];
}

double nice_number(double x, bool round) {
  if (!(x > 0.0) || !std::isfinite(x)) return 1.0;
  const double exponent = std::floor(std::log10(x));
  const double power = std::pow(10.0, exponent);
  const double f = x / power;  // in [1, 10)
  double nice;
  if (round) {
    nice = f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0;
  } else {
    nice = f <= 1.0 ? 1.0 : f <= 2.0 ? 2.0 : f <= 5.0 ? 5.0 : 10.0;
  }
  return nice * power;
}

Ticks nice_ticks(double lo, double hi, int target) {
  Ticks ticks;
  if (!std::isfinite(lo) || !std::isfinite(hi)) return ticks;
  if (lo > hi) std::swap(lo, hi);
  if (hi == lo) {
    const double pad = lo == 0.0 ? 1.0 : 0.1 * std::fabs(lo);
    lo -= pad;
    hi += pad;
  }
  target = std::max(target, 2);
  const double range = nice_number(hi - lo, false);
  ticks.step = nice_number(range / (target - 1), true);
  const double eps = 1e-9 * ticks.step;
  const double first = std::ceil((lo - eps) / ticks.step);
  for (double k = first;; k += 1.0) {
    double v = k * ticks.step;
    if (v > hi + eps) break;
    if (std::fabs(v) < 1e-6 * ticks.step) v = 0.0;
    ticks.values.push_back(v);
    if (ticks.values.size() > 1000) break;
  }
  return ticks;
}

std::vector<double> log_major_ticks(double lo, double hi) {
  std::vector<double> ticks;
  if (!(lo > 0.0) || !(hi >= lo) || !std::isfinite(hi)) return ticks;
  const double eps = 1e-9;
  const int k0 = static_cast<int>(std::ceil(std::log10(lo) - eps));
  const int k1 = static_cast<int>(std::floor(std::log10(hi) + eps));
  for (int k = k0; k <= k1; ++k) ticks.push_back(std::pow(10.0, k));
  return ticks;
}

std::vector<double> log_minor_ticks(double lo, double hi) {
  std::vector<double> ticks;
  if (!(lo > 0.0) || !(hi >= lo) || !std::isfinite(hi)) return ticks;
  const int k0 = static_cast<int>(std::floor(std::log10(lo)));
  const int k1 = static_cast<int>(std::floor(std::log10(hi)));
  for (int k = k0; k <= k1; ++k) {
    const double decade = std::pow(10.0, k);
    for (int m = 2; m <= 9; ++m) {
      const double v = m * decade;
      if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) ticks.push_back(v);
    }
  }
  return ticks;
}

std::string format_tick(double value, double step) {
  char buffer[48];
  if (std::fabs(value) < 1e-6 * std::fabs(step)) return "0";
  const double magnitude = std::fabs(value);
  if (magnitude >= 1e6 || (step > 0.0 && step < 1e-4)) {
    // Enough significant digits to tell neighbouring ticks apart.
    const int digits = std::clamp(
        static_cast<int>(std::floor(std::log10(magnitude)) - std::floor(std::log10(step))), 0, 8);
    std::snprintf(buffer, sizeof(buffer), "%.*e", digits, value);
    return buffer;
  }
  const int decimals =
      step > 0.0 ? std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 10) : 0;
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

Range axis_range(const Axis& axis, const std::vector<const std::vector<double>*>& values) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  for (const std::vector<double>* v : values) {
    for (double x : *v) {
      if (!usable(x, axis.scale)) continue;
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
  if (axis.min) lo = *axis.min;
  if (axis.max) hi = *axis.max;
  Range r;
  if (axis.scale == Scale::kLog10) {
    if (!(lo > 0.0) || !std::isfinite(lo)) lo = axis.max ? *axis.max / 10.0 : 1.0;
    if (!(hi >= lo) || !std::isfinite(hi)) hi = lo * 10.0;
    if (hi == lo) {
      lo /= std::sqrt(10.0);
      hi *= std::sqrt(10.0);
    }
    const double a = std::log10(lo), b = std::log10(hi);
    if (b - a >= 1.0) {
      r.lo = axis.min ? lo : std::pow(10.0, std::floor(a + 1e-9));
      r.hi = axis.max ? hi : std::pow(10.0, std::ceil(b - 1e-9));
    } else {
      const double margin = 0.05 * (b - a);
      r.lo = axis.min ? lo : std::pow(10.0, a - margin);
      r.hi = axis.max ? hi : std::pow(10.0, b + margin);
    }
    return r;
  }
  if (!std::isfinite(lo) || !std::isfinite(hi)) {
    lo = axis.min ? *axis.min : axis.max ? *axis.max - 1.0 : 0.0;
    hi = lo + 1.0;
  }
  if (hi < lo) std::swap(lo, hi);
  const Ticks ticks = nice_ticks(lo, hi, 6);
  r.lo = axis.min ? lo : std::floor(lo / ticks.step + 1e-9) * ticks.step;
  r.hi = axis.max ? hi : std::ceil(hi / ticks.step - 1e-9) * ticks.step;
  if (!(r.hi > r.lo)) {
    r.lo -= ticks.step;
    r.hi += ticks.step;
  }
  return r;
}

cv::Mat render(const Figure& figure) {
  const int panels = std::max<int>(1, static_cast<int>(figure.panels.size()));
  const int title_height =
      figure.title.empty() ? 0 : text_size(figure.title, kFigureTitleFont, 2).height + 20;
  cv::Mat image(figure.panel_height + title_height, figure.panel_width * panels, CV_8UC3, kWhite);
  if (!figure.title.empty()) {
    const cv::Size size = text_size(figure.title, kFigureTitleFont, 2);
    put_text(image, figure.title, cv::Point(image.cols / 2 - size.width / 2, 12), kFigureTitleFont, 2);
  }
  for (std::size_t i = 0; i < figure.panels.size(); ++i) {
    const cv::Rect rect(static_cast<int>(i) * figure.panel_width, title_height, figure.panel_width,
                        figure.panel_height);
    draw_panel(image, rect, figure.panels[i]);
  }
  return image;
}

std::string write_png(const Figure& figure, const std::string& path) {
  const cv::Mat image = render(figure);
  try {
    if (!cv::imwrite(path, image)) return path + ": cannot write the PNG";
  } catch (const cv::Exception& e) {
    return path + ": cannot write the PNG: " + e.what();
  }
  return {};
}

}  // namespace hadal::validation::plot

#include "core/plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.h"
#include "core/text.h"

namespace isoatlas {
namespace {

using Rgb = std::array<std::uint8_t, 3>;
constexpr Rgb kBlack{0, 0, 0}, kGrid{225, 225, 225};
constexpr Rgb kColours[] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {255, 127, 14},
                            {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {23, 190, 207}};

void fillRect(Image& image, int x0, int y0, int x1, int y1, Rgb c) {
  for (int y = std::max(0, y0); y <= std::min(image.height - 1, y1); ++y)
    for (int x = std::max(0, x0); x <= std::min(image.width - 1, x1); ++x) std::copy(c.begin(), c.end(), image.at(x, y));
}

// A line `thickness` pixels wide, by steps along its longer axis; dashed: 8 steps drawn, 6 left.
void drawLine(Image& image, double x0, double y0, double x1, double y1, Rgb c, int thickness, bool dashed = false) {
  const int steps = int(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
  for (int s = 0; s <= steps; ++s) {
    if (dashed && s % 14 >= 8) continue;
    const double t = double(s) / steps;
    const int x = int(std::lround(x0 + (x1 - x0) * t)), y = int(std::lround(y0 + (y1 - y0) * t));
    fillRect(image, x - thickness / 2, y - thickness / 2, x + (thickness - 1) / 2, y + (thickness - 1) / 2, c);
  }
}

// Round-number ticks (1, 2 or 5 times a power of ten) covering [lo, hi], about `count` of them;
// a range too narrow for its numbers to tell apart is widened first.
std::vector<double> ticks(double& lo, double& hi, int count) {
  if (!(hi - lo > 1e-9 * std::max(std::abs(lo), std::abs(hi)))) lo -= 1, hi += 1;
  const double raw = (hi - lo) / count, power = std::pow(10, std::floor(std::log10(raw)));
  double step = power;
  for (const double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= raw) {
      step = m * power;
      break;
    }
  lo = std::floor(lo / step) * step, hi = std::ceil(hi / step) * step;
  std::vector<double> out;
  const long long steps = std::llround((hi - lo) / step);
  for (long long k = 0; k <= steps; ++k) {
    const double v = lo + double(k) * step;
    out.push_back(std::abs(v) < step * 1e-9 ? 0 : v);
  }
  return out;
}

std::string label(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

Image linePlot(const std::vector<PlotSeries>& series, const PlotOptions& o) {
  require(o.width >= 200 && o.height >= 150 && o.width <= 8192 && o.height <= 8192, "plot size out of range");
  double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo, ylo = xlo, yhi = -xlo;
  for (const PlotSeries& s : series) {
    require(s.x.size() == s.y.size(), "plot: a series has " + std::to_string(s.x.size()) + " x and " + std::to_string(s.y.size()) + " y values");
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]))
        xlo = std::min(xlo, s.x[i]), xhi = std::max(xhi, s.x[i]), ylo = std::min(ylo, s.y[i]), yhi = std::max(yhi, s.y[i]);
  }
  if (!std::isfinite(xlo)) xlo = 0, xhi = 1, ylo = 0, yhi = 1;  // nothing finite (an exact model): empty axes
  const std::vector<double> xt = ticks(xlo, xhi, 10), yt = ticks(ylo, yhi, 6);
  Image image(o.width, o.height, 3);
  std::fill(image.pixels.begin(), image.pixels.end(), 255);
  const int font = std::max(12, o.height / 36);
  const int left = font * 5, right = o.width - font, top = font * 4, bottom = o.height - font * 4;
  auto px = [&](double x) { return left + (x - xlo) / (xhi - xlo) * (right - left); };
  auto py = [&](double y) { return bottom - (y - ylo) / (yhi - ylo) * (bottom - top); };
  for (const double y : yt) {
    drawLine(image, left, py(y), right, py(y), kGrid, 1);
    const std::string t = label(y);
    drawText(image, left - font / 2 - int(t.size()) * font * 6 / 10, int(py(y)) - font * 2 / 3, t, font, kBlack);
  }
  for (const double x : xt) {
    drawLine(image, px(x), top, px(x), bottom, kGrid, 1);
    const std::string t = label(x);
    drawText(image, int(px(x)) - int(t.size()) * font * 3 / 10, bottom + font / 3, t, font, kBlack);
  }
  drawLine(image, left, bottom, right, bottom, kBlack, 2);
  drawLine(image, left, top, left, bottom, kBlack, 2);
  if (!o.title.empty()) drawText(image, left, font / 2, o.title, font * 5 / 4, kBlack);
  if (!o.xLabel.empty()) drawText(image, (left + right) / 2 - int(o.xLabel.size()) * font * 3 / 10, bottom + font * 2, o.xLabel, font, kBlack);
  if (!o.yLabel.empty()) drawText(image, font / 4, top - font * 2, o.yLabel, font, kBlack);
  for (std::size_t k = 0; k < series.size(); ++k) {
    const PlotSeries& s = series[k];
    const Rgb c = kColours[std::size_t(s.colour >= 0 ? s.colour : int(k)) % std::size(kColours)];
    bool have = false;
    double lx = 0, ly = 0;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) {
        have = false;
        continue;
      }
      const double x = px(s.x[i]), y = py(s.y[i]);
      if (have) drawLine(image, lx, ly, x, y, c, 3, s.dashed);
      fillRect(image, int(x) - 4, int(y) - 4, int(x) + 4, int(y) + 4, c);
      lx = x, ly = y, have = true;
    }
    // Legend, top left inside the axes.
    const int ly0 = top + font / 2 + int(k) * font * 3 / 2;
    drawLine(image, left + font, ly0 + font / 2, left + font * 2, ly0 + font / 2, c, 4, s.dashed);
    drawText(image, left + font * 5 / 2, ly0 - font / 6, s.name, font, kBlack);
  }
  return image;
}

}  // namespace isoatlas

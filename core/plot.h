// linePlot: a line chart as a PNG-ready RGB image: axes with round-number ticks, labels, a title,
// one coloured line (solid or dashed) with markers per series and a legend. Points whose x or y is not finite (the
// PSNR of an exact level) are left out; with none left the axes are drawn empty.
#pragma once
#include <string>
#include <vector>

#include "core/image.h"

namespace isoatlas {

struct PlotSeries {
  std::string name;
  std::vector<double> x, y;
  int colour = -1;      // the palette's colour of that index; -1: the series' own place
  bool dashed = false;  // a dashed line (a second measure of a series drawn solid)
};
struct PlotOptions {
  std::string title, xLabel, yLabel;
  int width = 900, height = 560;
};

Image linePlot(const std::vector<PlotSeries>& series, const PlotOptions& options);

}  // namespace isoatlas

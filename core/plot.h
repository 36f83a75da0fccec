// linePlot: a line chart as a PNG-ready RGB image: axes with round-number ticks, labels, a title,
// one coloured line with markers per series and a legend. Points whose x or y is not finite (the
// PSNR of an exact level) are left out; with none left the axes are drawn empty.
#pragma once
#include <string>
#include <vector>

#include "core/image.h"

namespace isoatlas {

struct PlotSeries {
  std::string name;
  std::vector<double> x, y;
};
struct PlotOptions {
  std::string title, xLabel, yLabel;
  int width = 900, height = 560;
};

Image linePlot(const std::vector<PlotSeries>& series, const PlotOptions& options);

}  // namespace isoatlas

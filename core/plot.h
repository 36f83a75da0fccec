// linePlot: a line chart as a PNG-ready RGB image: axes with round-number ticks, labels, a title,
// one coloured line with markers per series and a legend. Points whose y is not finite are left out.
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

#include "atlas/evaluate_levels.h"

#include "atlas/reconstruct.h"
#include "core/mesh_topology.h"
#include "core/plot.h"
#include "core/progress.h"

#include <tbb/parallel_invoke.h>

#include <optional>

namespace isoatlas::atlas {

// One level measured at a time, with both cores (MeshDistances::to measures both ways side by side),
// while the next level is reconstructed beside it (one core's work).
std::vector<LevelFigures> evaluateLevels(const multires::BaseMesh& base, const Atlas& atlas, const Mesh& dense,
                                         const std::vector<int>& levels, std::size_t facePoints) {
  const double diagonal = boundingBox(dense.positions).diagonal();
  std::optional<MeshDistances> fromDense;  // the dense samples and tree, once for every level
  std::optional<Mesh> next;
  const auto reconstructNext = [&](std::size_t i) {
    if (i < levels.size()) next = reconstructLevel(base, atlas, levels[i]);
  };
  tbb::parallel_invoke([&] { fromDense.emplace(dense, facePoints); }, [&] { reconstructNext(0); });
  std::vector<LevelFigures> out;
  Progress progress("eval: levels", levels.size(), "levels");
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const Mesh mesh = std::move(*next);
    MeshTopology topology;
    Hausdorff h;
    tbb::parallel_invoke([&] { h = fromDense->to(mesh, &topology); }, [&] { reconstructNext(i + 1); });
    out.push_back({levels[i], mesh.vertexCount(), mesh.faceCount(), h.symmetric(), psnrDb(diagonal, h.symmetric()), h.rms(),
                   psnrDb(diagonal, h.rms()), topology.closed, topology.manifold});
    progress.update(out.size());
  }
  progress.finish();
  return out;
}

Image psnrPlot(const std::vector<std::pair<std::string, std::vector<LevelFigures>>>& models) {
  std::vector<PlotSeries> series;
  for (const auto& [name, levels] : models) {
    const int colour = int(series.size() / 2);
    PlotSeries s{name, {}, {}, colour, false}, rms{name + " (RMS)", {}, {}, colour, true};
    for (const auto& l : levels) s.x.push_back(l.level), s.y.push_back(l.psnrDb), rms.x.push_back(l.level), rms.y.push_back(l.psnrRmsDb);
    series.push_back(std::move(s));
    series.push_back(std::move(rms));
  }
  return linePlot(series, {.title = "Accuracy per level (CGAL: largest distance to the dense mesh, and RMS)",
                           .xLabel = "level (0: base mesh; 2 log2(N-1): the whole chart)",
                           .yLabel = "PSNR (dB)"});
}

}  // namespace isoatlas::atlas

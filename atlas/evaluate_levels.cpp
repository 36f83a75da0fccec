#include "atlas/evaluate_levels.h"

#include "atlas/reconstruct.h"
#include "core/mesh_topology.h"
#include "core/plot.h"
#include "core/progress.h"

#include <tbb/parallel_for_each.h>

#include <algorithm>
#include <mutex>
#include <numeric>


namespace isoatlas::atlas {

// The levels side by side, the finest first: the parts of one level that run on one core (its
// reconstruction, its tree's nodes, its topology) leave the other core to the next level.
std::vector<LevelFigures> evaluateLevels(const multires::BaseMesh& base, const Atlas& atlas, const Mesh& dense,
                                         const std::vector<int>& levels, std::size_t facePoints) {
  const double diagonal = boundingBox(dense.positions).diagonal();
  const MeshDistances fromDense(dense, facePoints);  // the dense samples and tree, once for every level
  std::vector<LevelFigures> out(levels.size());
  std::vector<std::size_t> finestFirst(levels.size());
  std::iota(finestFirst.begin(), finestFirst.end(), 0);
  std::stable_sort(finestFirst.begin(), finestFirst.end(), [&](std::size_t a, std::size_t b) { return levels[a] > levels[b]; });
  Progress progress("eval: levels", levels.size(), "levels");
  std::mutex progressLock;
  std::size_t done = 0;
  tbb::parallel_for_each(finestFirst.begin(), finestFirst.end(), [&](std::size_t i) {
    const Mesh mesh = reconstructLevel(base, atlas, levels[i]);
    MeshTopology topology;
    const Hausdorff h = fromDense.to(mesh, &topology);
    out[i] = {levels[i], mesh.vertexCount(), mesh.faceCount(), h.symmetric(), psnrDb(diagonal, h.symmetric()), h.rms(),
              psnrDb(diagonal, h.rms()), topology.closed, topology.manifold};
    const std::lock_guard lock(progressLock);
    progress.update(++done);
  });
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

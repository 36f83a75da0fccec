#include "pipeline/surface_figures.h"

#include "core/mesh_topology.h"

namespace isoatlas::pipeline {

nlohmann::json surfaceFigures(const Mesh& mesh, const extract::ExtractStats* stats) {
  const MeshTopology t = analyzeTopology(mesh);
  nlohmann::json figures{{"vertices", mesh.vertexCount()}, {"triangles", mesh.faceCount()}, {"components", t.components},
                         {"closed", t.closed}, {"manifold", t.manifold}, {"euler", t.euler}, {"genus", t.genus},
                         {"area_mm2", surfaceArea(mesh)}};
  if (stats)
    figures.update({{"seconds", stats->seconds}, {"cells_visited", stats->cellsVisited}, {"cells_total", stats->cellsTotal},
                    {"iso", stats->iso}, {"binary_input", stats->binaryInput}, {"path", stats->path}, {"gpu_bytes", stats->gpuBytes}});
  return figures;
}

}  // namespace isoatlas::pipeline

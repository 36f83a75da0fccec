// surfaceFigures: what every extracted surface reports (isoatlas extract, run, edit to a mesh, the
// Python module and the cohort table): its size, topology (analyzeTopology's) and area, and, when the
// extraction's statistics are given, how it was made.
//   mesh   any polygon mesh, positions in world mm
//   stats  the extraction's statistics, or none for a mesh from elsewhere
// Gives vertices, triangles, components, closed, manifold, euler, genus, area_mm2, then seconds,
// cells_visited, cells_total, iso, binary_input, path and gpu_bytes with stats.
#pragma once
#include <nlohmann/json.hpp>

#include "core/mesh.h"
#include "extract/extract_surface.h"

namespace isoatlas::pipeline {

nlohmann::json surfaceFigures(const Mesh& mesh, const extract::ExtractStats* stats = nullptr);

}  // namespace isoatlas::pipeline

// bench/multires: isoatlas's stellar simplification + triangle pairing beside CGAL's edge collapse
// with Garland-Heckbert plane policies and meshoptimizer's simplifier, at the same base size (the
// face count isoatlas's base mesh reaches at its default size), on bunny00, elephant, fandisk and
// the white-matter surface of ch2better (3 million triangles). Figures: seconds (isoatlas: simplify
// plus match), base vertices, symmetric Hausdorff distance to the dense mesh and PSNR, all measured
// by CGAL's approximate_Hausdorff_distance (core/distance/mesh_distance).
#include <chrono>
#include <filesystem>

#include "bench/bench_util.h"
#include "bench/cgal_simplify.h"
#include "bench/derived_data.h"
#include "bench/meshopt_simplify.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "extract/extract_surface.h"
#include "core/distance/mesh_distance.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"

using namespace isoatlas;

namespace {

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void compare(const std::string& name, const Mesh& dense) {
  const double diagonal = boundingBox(dense.positions).diagonal();
  std::fprintf(stderr, "multires: %s, %zu triangles\n", name.c_str(), dense.faceCount());

  auto start = std::chrono::steady_clock::now();
  multires::SimplifyStats stats;
  multires::BaseMesh base = multires::simplifyStellar(dense, {}, &stats);
  double ours = since(start);
  const std::size_t baseEdges = analyzeTopology(base.triangleMesh()).edges;  // CGAL's stop, untimed
  start = std::chrono::steady_clock::now();
  multires::pairTriangles(base, dense);
  ours += since(start);
  const Mesh ourMesh = base.triangleMesh();

  double cgalSeconds = 0, meshoptSeconds = 0;
  const Mesh cgal = bench::cgalSimplify(dense, baseEdges, cgalSeconds);
  const Mesh meshopt = bench::meshoptSimplify(dense, 2 * baseEdges / 3, meshoptSeconds);

  const double hOurs = hausdorffDistance(dense, ourMesh).symmetric();
  const double hCgal = hausdorffDistance(dense, cgal).symmetric();
  const double hMeshopt = hausdorffDistance(dense, meshopt).symmetric();
  const std::string caseName = name + " (" + std::to_string(dense.faceCount()) + " triangles)";
  const std::string cgalName = "CGAL 5.5 edge_collapse, Garland-Heckbert plane policies";
  const std::string meshoptName = "meshoptimizer 0.18 meshopt_simplify";
  bench::report("multires", caseName, "seconds to base mesh (isoatlas: simplify + match)", ours, cgalName, cgalSeconds);
  bench::report("multires", caseName, "seconds to base mesh (isoatlas: simplify + match)", ours, meshoptName, meshoptSeconds);
  bench::report("multires", caseName, "base vertices", double(base.vertexCount()), cgalName, double(cgal.vertexCount()), false);
  bench::report("multires", caseName, "base vertices", double(base.vertexCount()), meshoptName, double(meshopt.vertexCount()), false);
  bench::report("multires", caseName, "Hausdorff to the dense mesh (mm)", hOurs, cgalName, hCgal);
  bench::report("multires", caseName, "Hausdorff to the dense mesh (mm)", hOurs, meshoptName, hMeshopt);
  // PSNR: higher is better; the ratio column is ours / theirs in dB.
  bench::report("multires", caseName, "base PSNR (dB)", psnrDb(diagonal, hOurs), cgalName,
                psnrDb(diagonal, hCgal), false);
  bench::report("multires", caseName, "base PSNR (dB)", psnrDb(diagonal, hOurs), meshoptName,
                psnrDb(diagonal, hMeshopt), false);
}

}  // namespace

// bench_multires [DATA [NAME ...]]: NAME is a mesh in DATA/meshes (without .off) or "white-matter";
// without names, the four.
int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : "data";
  std::vector<std::string> names(argv + std::min(argc, 2), argv + argc);
  if (names.empty()) names = {"bunny00", "elephant", "fandisk", "white-matter"};
  for (const std::string& name : names) {
    if (name == "white-matter")
      compare("ch2better white matter",
              extract::extractSurface(bench::ch2betterWhiteMatterPhi(data), {.iso = 0.0f, .largestComponents = 1}));
    else
      compare(name, readMesh(data + "/meshes/" + name + ".off"));
  }
  return 0;
}

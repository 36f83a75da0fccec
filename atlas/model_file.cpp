#include "atlas/model_file.h"

#include <tbb/parallel_for.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>

#include "core/error.h"
#include "core/memory_budget.h"
#include "atlas/quantised_atlas.h"
#include "core/sectioned_file.h"

namespace isoatlas::atlas {
namespace {

constexpr char kMagic[8] = {'I', 'S', 'O', 'A', 'T', 'L', 'A', 'S'};

using Writer = SectionWriter;
using Reader = SectionReader;

// What the reader refuses in a base mesh beyond counts and ranges, or "" when it is sound: split
// vertices' dense indices, triangles naming a vertex twice, a triangle in two tiles, tiles whose
// triangles share no edge or whose quad repeats a corner.
std::string baseMeshProblem(const multires::BaseMesh& b) {
  if (b.denseVertex.size() != b.positions.size()) return "the base vertices' dense indices do not match their count";
  for (const Vec3& p : b.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return "a base vertex is not finite";
  for (std::size_t t = 0; t < b.triangleCount(); ++t) {
    const auto& c = b.triangles[t];
    if (c[0] >= b.vertexCount() || c[1] >= b.vertexCount() || c[2] >= b.vertexCount()) return "base triangle " + std::to_string(t) + " names a missing vertex";
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) return "base triangle " + std::to_string(t) + " names a vertex twice";
  }
  if (b.tiles.empty() || b.tiles.size() * 2 != b.triangleCount()) return "the base triangles are not all paired into tiles";
  std::vector<char> used(b.triangleCount(), 0);
  for (std::uint32_t t = 0; t < b.tiles.size(); ++t) {
    const auto [first, second] = b.tiles[t];
    if (first >= b.triangleCount() || second >= b.triangleCount() || used[first] || used[second] || first == second)
      return "tile " + std::to_string(t) + " names a missing triangle or one in another tile";
    used[first] = used[second] = 1;
    multires::BaseMesh::TileCorners c;
    try {
      c = b.tileCorners(t);
    } catch (const Error&) {
      return "tile " + std::to_string(t) + "'s triangles share no edge";
    }
    if (c.s == c.r) return "tile " + std::to_string(t) + " repeats a corner";
  }
  return "";
}

void readBase(Reader& r, multires::BaseMesh& b) {
  const std::uint64_t nv = r.count(32, "base vertex");
  for (std::uint64_t i = 0; i < nv; ++i) {
    b.positions.push_back(r.vec());
    const std::int64_t d = r.get<std::int64_t>();
    if (d < -1) r.fail("dense vertex " + std::to_string(d));
    b.denseVertex.push_back(d);
  }
  const std::uint64_t nt = r.count(12, "base triangle");
  for (std::uint64_t t = 0; t < nt; ++t)
    b.triangles.push_back({r.index(nv, "base vertex"), r.index(nv, "base vertex"), r.index(nv, "base vertex")});
  const std::uint64_t tiles = r.count(8, "tile");
  for (std::uint64_t t = 0; t < tiles; ++t) b.tiles.push_back({r.index(nt, "tile triangle"), r.index(nt, "tile triangle")});
  if (const std::string problem = baseMeshProblem(b); !problem.empty()) r.fail(problem);
}

void readLayout(Reader& r, std::uint32_t chartSize, std::size_t tiles, AtlasLayout& l) {
  l.chartSize = chartSize;
  l.charts = r.get<std::uint32_t>(), l.columns = r.get<std::uint32_t>(), l.rows = r.get<std::uint32_t>();
  if (l.charts == 0 || std::uint64_t(l.columns) * l.rows < l.charts || std::uint64_t(l.columns) * l.rows > l.charts + std::uint64_t(l.columns))
    r.fail(std::to_string(l.columns) + " x " + std::to_string(l.rows) + " slots for " + std::to_string(l.charts) + " charts");
  if (l.columns > l.charts) r.fail(std::to_string(l.columns) + " columns for " + std::to_string(l.charts) + " charts");  // never packed so
  if (l.charts != tiles) r.fail("the atlas's chart count is not the tile count");
}

// Versions 3 and 4: per chart its box, then its codes: version 3 as they are (N x N positions, then
// N x N octahedral normals), version 4 packed (packChartCodes: a length, then deflated bytes).
void readQuantisedAtlas(Reader& r, std::uint32_t version, std::uint32_t chartSize, const multires::BaseMesh& base, Atlas& atlas,
                        std::vector<QuantisedChart>& charts) {
  readLayout(r, chartSize, base.tiles.size(), atlas.layout);
  const std::uint64_t texels = std::uint64_t(chartSize) * chartSize;
  if (version == 3) {
    const std::uint64_t chartBytes = 24 + texels * 8;  // f32 x 6, then u16 x 3 and u8 x 2 a texel
    r.fits(atlas.layout.charts, chartBytes, "chart");
    if (atlas.layout.charts * chartBytes != r.left()) r.fail("the charts take " + std::to_string(atlas.layout.charts * chartBytes) +
                                                             " bytes, the section holds " + std::to_string(r.left()));
  } else {
    r.fits(atlas.layout.charts, 28, "chart");  // f32 x 6 and a length, at least
    // Deflated codes inflate a thousandfold: the charts' codes and the atlas image they decode to
    // are held to the memory budget before any is unpacked.
    const double slots = double(atlas.layout.columns) * atlas.layout.rows, perChart = double(texels);
    const double bytes = perChart * (atlas.layout.charts * double(sizeof(QuantisedChart::positions[0]) + sizeof(QuantisedChart::normals[0])) +
                                     slots * double(sizeof(atlas.positions[0]) + sizeof(atlas.normals[0])));
    requireWithinMemoryBudget(bytes < 1.8e19 ? std::uint64_t(bytes) : ~std::uint64_t(0),
                              r.path() + ": the atlas's " + std::to_string(atlas.layout.charts) + " charts of " + std::to_string(chartSize) +
                                  " x " + std::to_string(chartSize) + " texels");
  }
  charts.assign(atlas.layout.charts, {});
  for (QuantisedChart& q : charts) {
    for (float& x : q.lo) x = r.finite<float>();
    for (float& x : q.step)
      if ((x = r.finite<float>()) < 0) r.fail("a chart's quantisation step is negative");
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(q.lo[a] + 65535.0f * q.step[a])) r.fail("a chart's box reaches past the largest float");
    if (version == 3) {
      q.positions.resize(texels);
      for (auto& p : q.positions) p = {r.get<std::uint16_t>(), r.get<std::uint16_t>(), r.get<std::uint16_t>()};
      q.normals.resize(texels);
      for (auto& n : q.normals) n = {r.get<std::uint8_t>(), r.get<std::uint8_t>()};
      continue;
    }
    const std::uint32_t size = r.get<std::uint32_t>();
    if (!unpackChartCodes(r.take(size), size, chartSize, q)) r.fail("a chart's codes do not inflate to " + std::to_string(texels) + " texels");
  }
  dequantiseAtlas(charts, base, atlas);
}

// Version 2: the atlas image as floats and 16-bit normals, empty slots included.
void readFloatAtlas(Reader& r, std::uint32_t chartSize, std::size_t tiles, Atlas& atlas) {
  AtlasLayout& l = atlas.layout;
  readLayout(r, chartSize, tiles, l);
  const std::uint64_t texelBytes = 18;  // f32 x 3 + i16 x 3
  r.fits(std::uint64_t(l.columns) * l.rows, texelBytes * chartSize * chartSize, "atlas slot");
  const std::uint64_t texels = std::uint64_t(l.width()) * l.height();
  if (texels * texelBytes != r.left()) r.fail("the atlas images take " + std::to_string(texels * texelBytes) + " bytes, the section holds " +
                                               std::to_string(r.left()));
  atlas.positions.resize(texels);
  for (auto& p : atlas.positions) p = {r.finite<float>(), r.finite<float>(), r.finite<float>()};
  atlas.normals.resize(texels);
  for (auto& n : atlas.normals) n = {r.get<std::int16_t>(), r.get<std::int16_t>(), r.get<std::int16_t>()};
}

void readDetails(Reader& r, std::uint32_t chartSize, std::size_t tiles, std::vector<DetailChart>& details) {
  const std::uint32_t count = r.get<std::uint32_t>(), size = r.get<std::uint32_t>();
  if (!multires::isChartSize(size) || size <= chartSize) r.fail("detail chart size " + std::to_string(size));
  const std::uint64_t texels = std::uint64_t(size) * size;
  r.fits(count, 4 + texels * 18, "detail chart");
  for (std::uint32_t k = 0; k < count; ++k) {
    DetailChart d{r.index(tiles, "detail tile"), size, std::vector<std::array<float, 3>>(texels), std::vector<Normal16>(texels)};
    if (!details.empty() && d.tile <= details.back().tile) r.fail("detail charts out of tile order");
    for (auto& p : d.positions) p = {r.finite<float>(), r.finite<float>(), r.finite<float>()};
    for (auto& n : d.normals) n = {r.get<std::int16_t>(), r.get<std::int16_t>(), r.get<std::int16_t>()};
    details.push_back(std::move(d));
  }
}

void readDense(Reader& r, Mesh& m) {
  const std::uint64_t nv = r.count(24, "vertex");
  m.positions.resize(nv);
  for (auto& p : m.positions) p = r.vec();
  const std::uint64_t nt = r.count(12, "triangle");
  for (std::uint64_t t = 0; t < nt; ++t) {
    const std::uint32_t a = r.index(nv, "vertex"), b = r.index(nv, "vertex"), c = r.index(nv, "vertex");
    m.addFace({a, b, c});
  }
}

void readParametrisation(Reader& r, multires::BaseMesh& b) {
  const std::uint64_t nd = r.count(28, "parametrised vertex");
  for (std::uint64_t i = 0; i < nd; ++i) {
    b.denseTriangle.push_back(r.index(b.triangleCount(), "base triangle"));
    b.denseBary.push_back({r.finite<double>(), r.finite<double>(), r.finite<double>()});
  }
}

}  // namespace

std::vector<BaseHalfedge> baseHalfedges(const multires::BaseMesh& base, std::uint32_t chartSize) {
  const std::uint8_t last = std::uint8_t(chartSize - 1);
  std::vector<BaseHalfedge> out(base.triangleCount() * 3);
  for (std::uint32_t tile = 0; tile < base.tiles.size(); ++tile) {
    const auto c = base.tileCorners(tile);
    auto uvOf = [&](std::uint32_t v) -> std::array<std::uint8_t, 2> {
      if (v == c.p) return {0, 0};
      if (v == c.s) return {last, 0};
      if (v == c.q) return {last, last};
      return {0, last};
    };
    for (const std::uint32_t t : base.tiles[tile])
      for (int k = 0; k < 3; ++k) {
        const auto from = uvOf(base.triangles[t][k]), to = uvOf(base.triangles[t][(k + 1) % 3]);
        out[t * 3 + k] = {tile, {from[0], from[1], to[0], to[1]}};
      }
  }
  return out;
}

std::uint64_t halfedgeMeshBytes(const Mesh& mesh) {
  std::uint64_t halfedges = 0;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) halfedges += mesh.face(f).size();
  return mesh.vertexCount() * (12 + 4) + halfedges * 16 + mesh.faceCount() * 4;
}

std::uint64_t binaryPlyBytes(const Mesh& mesh) {
  std::uint64_t corners = 0;
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) corners += mesh.face(f).size();
  return mesh.vertexCount() * 12 + mesh.faceCount() + corners * 4;
}

double writeModel(const std::string& path, const Model& model) {
  // Checked before the file is touched, so a refused model loses nothing already there.
  require(multires::isChartSize(model.chartSize), path + ": chart size " + std::to_string(model.chartSize) +
                                                      " is not 2^k + 1 between 3 and " +
                                                      std::to_string(multires::kMaxChartSize));
  const multires::BaseMesh& b = model.base;
  if (const std::string problem = baseMeshProblem(b); !problem.empty()) throw Error(path + ": " + problem);
  const AtlasLayout& l = model.atlas.layout;
  require(l.chartSize == model.chartSize && l.charts == b.tiles.size() &&
              std::uint64_t(l.columns) * l.rows >= l.charts && std::uint64_t(l.columns) * l.rows <= l.charts + std::uint64_t(l.columns) &&
              model.atlas.positions.size() == std::size_t(l.width()) * l.height() &&
              model.atlas.normals.size() == model.atlas.positions.size(),
          path + ": the atlas does not match the base mesh's tiles and the chart size");
  auto finite = [](const std::vector<std::array<float, 3>>& points) {
    for (const auto& p : points)
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) return false;
    return true;
  };
  require(finite(model.atlas.positions), path + ": an atlas position is not finite");
  for (std::size_t k = 0; k < model.atlas.details.size(); ++k) {
    const DetailChart& d = model.atlas.details[k];
    require(d.size == model.atlas.details.front().size && multires::isChartSize(d.size) && d.size > model.chartSize &&
                d.tile < b.tiles.size() && (k == 0 || d.tile > model.atlas.details[k - 1].tile) &&
                d.positions.size() == std::size_t(d.size) * d.size && d.normals.size() == d.positions.size(),
            path + ": detail chart " + std::to_string(k) + " does not fit the model");
    require(finite(d.positions), path + ": a position of detail chart " + std::to_string(k) + " is not finite");
  }
  const bool dense = model.dense.vertexCount() > 0;
  require(!dense || model.dense.allFacesHave(3), path + ": the dense mesh must be triangles");
  require(!dense || (b.denseTriangle.size() == model.dense.vertexCount() && b.denseBary.size() == b.denseTriangle.size()),
          path + ": the dense mesh is kept without its parametrisation");
  if (dense) {
    for (const std::uint32_t c : model.dense.faceVertices) require(c < model.dense.vertexCount(), path + ": a dense triangle names a missing vertex");
    for (const std::uint32_t t : b.denseTriangle) require(t < b.triangleCount(), path + ": a dense vertex lies in a missing base triangle");
    for (const std::int64_t d : b.denseVertex) require(d < std::int64_t(model.dense.vertexCount()), path + ": a base vertex names a missing dense vertex");
  }

  SectionedFileWriter out(path, kMagic, kModelVersion);

  Writer head;
  const bool keepCodes = decodesTo(model.codes, b, model.atlas);
  Atlas decoded;
  const std::vector<QuantisedChart> charts = keepCodes ? model.codes : quantiseAtlas(model.atlas, b, nullptr, &decoded);
  const double quantisationError = keepCodes ? model.quantisationError : largestQuantisationError(model.atlas, decoded);
  head.put(model.chartSize), head.put(model.coincidentTexels), head.put(model.gapTexels), head.put(quantisationError);
  out.section("HEAD", head);

  Writer base;
  base.put(std::uint64_t(b.vertexCount()));
  for (std::size_t i = 0; i < b.vertexCount(); ++i) base.putVec(b.positions[i]), base.put(b.denseVertex[i]);
  base.put(std::uint64_t(b.triangleCount()));
  for (const auto& t : b.triangles) base.put(t[0]), base.put(t[1]), base.put(t[2]);
  base.put(std::uint64_t(b.tiles.size()));
  for (const auto& t : b.tiles) base.put(t[0]), base.put(t[1]);
  out.section("BASE", base);

  Writer half;
  for (const BaseHalfedge& h : baseHalfedges(b, model.chartSize)) {
    half.put(h.chart);
    for (const std::uint8_t x : h.uv) half.put(x);
  }
  for (std::size_t v = 0; v < b.vertexCount(); ++v) half.put(std::uint8_t(0));
  out.section("HALF", half);

  Writer atlas;
  atlas.put(l.charts), atlas.put(l.columns), atlas.put(l.rows);
  std::vector<std::vector<std::uint8_t>> packed(charts.size());
  tbb::parallel_for(std::size_t(0), charts.size(), [&](std::size_t c) { packed[c] = packChartCodes(charts[c], model.chartSize); });
  for (std::size_t c = 0; c < charts.size(); ++c) {
    for (const float x : charts[c].lo) atlas.put(x);
    for (const float x : charts[c].step) atlas.put(x);
    atlas.put(std::uint32_t(packed[c].size()));
    atlas.putBytes(packed[c]);
  }
  out.section("ATLS", atlas);

  if (!model.atlas.details.empty()) {
    Writer detail;
    detail.put(std::uint32_t(model.atlas.details.size())), detail.put(model.atlas.details.front().size);
    for (const DetailChart& d : model.atlas.details) {
      detail.put(d.tile);
      for (const auto& p : d.positions) detail.put(p[0]), detail.put(p[1]), detail.put(p[2]);
      for (const auto& n : d.normals) detail.put(n[0]), detail.put(n[1]), detail.put(n[2]);
    }
    out.section("DETL", detail);
  }

  if (dense) {
    Writer d;
    d.put(std::uint64_t(model.dense.vertexCount()));
    for (const Vec3& p : model.dense.positions) d.putVec(p);
    d.put(std::uint64_t(model.dense.faceCount()));
    for (const std::uint32_t c : model.dense.faceVertices) d.put(c);
    out.section("DENS", d);
    Writer para;
    para.put(std::uint64_t(b.denseTriangle.size()));
    for (std::size_t i = 0; i < b.denseTriangle.size(); ++i) {
      para.put(b.denseTriangle[i]);
      for (const double w : b.denseBary[i]) para.put(w);
    }
    out.section("PARA", para);
  }
  out.finish();
  return quantisationError;
}

Model readModel(const std::string& path, const ModelReadOptions& options) {
  const SectionedFile file = readSectionedFile(path, kMagic, "an isoatlas model file");
  const std::uint32_t version = file.version;
  if (version == 1)
    throw Error(path + ": model format version 1 holds no atlas; build the model again with this isoatlas (isoatlas build)");
  if (version != 2 && version != 3 && version != kModelVersion)
    throw Error(path + ": model format version " + std::to_string(version) + " (this isoatlas reads versions 2, 3 and " +
                std::to_string(kModelVersion) + ")");
  Model model;
  std::set<std::string> seen;
  forEachSection(file, options.checksums, [&](const std::string& tag, Reader& r) {
    const bool known = tag == "HEAD" || tag == "BASE" || tag == "HALF" || tag == "ATLS" || tag == "DETL" || tag == "DENS" || tag == "PARA";
    if (known && !seen.insert(tag).second) r.fail("a second " + tag + " section");  // would mix two models' counts
    // Each section may rely on those it names having come first.
    auto after = [&](const char* earlier) {
      if (!seen.count(earlier)) r.fail(std::string("comes before the ") + earlier + " section");
    };
    if (tag == "HEAD") {
      model.chartSize = r.get<std::uint32_t>();
      if (!multires::isChartSize(model.chartSize)) r.fail("chart size " + std::to_string(model.chartSize));
      model.coincidentTexels = r.get<std::uint64_t>(), model.gapTexels = r.get<std::uint64_t>();
      if (version >= 3 && (model.quantisationError = r.finite<double>()) < 0) r.fail("a negative quantisation error");
    } else if (tag == "BASE") {
      readBase(r, model.base);
    } else if (tag == "HALF") {
      after("HEAD"), after("BASE");
      const auto expected = baseHalfedges(model.base, model.chartSize);
      r.fits(expected.size(), 8, "halfedge");
      for (const BaseHalfedge& e : expected) {
        BaseHalfedge h{r.get<std::uint32_t>(), {}};
        for (auto& x : h.uv) x = r.get<std::uint8_t>();
        if (!(h == e)) r.fail("a halfedge's chart or (u, v) disagrees with the tiles");
      }
      r.fits(model.base.vertexCount(), 1, "vertex level");
      for (std::size_t v = 0; v < model.base.vertexCount(); ++v)
        if (r.get<std::uint8_t>() != 0) r.fail("a base vertex's level is not 0");
    } else if (tag == "ATLS") {
      after("HEAD"), after("BASE");
      if (version >= 3) readQuantisedAtlas(r, version, model.chartSize, model.base, model.atlas, model.codes);
      else readFloatAtlas(r, model.chartSize, model.base.tiles.size(), model.atlas);
    } else if (tag == "DETL") {
      after("HEAD"), after("BASE");
      readDetails(r, model.chartSize, model.base.tiles.size(), model.atlas.details);
    } else if (tag == "DENS") {
      readDense(r, model.dense);
    } else if (tag == "PARA") {
      after("BASE"), after("DENS");
      readParametrisation(r, model.base);
      if (model.base.denseTriangle.size() != model.dense.vertexCount())
        r.fail("the parametrisation covers " + std::to_string(model.base.denseTriangle.size()) + " vertices, the dense mesh has " +
               std::to_string(model.dense.vertexCount()));
    }
    if (known && !r.done()) r.fail("trailing bytes");
  });
  for (const char* tag : {"HEAD", "BASE", "HALF", "ATLS"})
    if (!seen.count(tag)) throw Error(path + ": the model lacks its " + std::string(tag) + " section");
  if (seen.count("DENS") != seen.count("PARA")) throw Error(path + ": the dense mesh comes without its parametrisation (DENS, PARA)");
  for (const std::int64_t d : model.base.denseVertex)
    if (seen.count("DENS") && d >= std::int64_t(model.dense.vertexCount())) throw Error(path + ": a base vertex names a missing dense vertex");
  return model;
}

}  // namespace isoatlas::atlas

#include "multires/dense_sampler.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "multires/base_domain.h"

namespace isoatlas::multires {

DenseSampler::DenseSampler(const Mesh& dense, const BaseMesh& base, bool indexed)
    : dense_(dense), images_(base.triangleCount()), foldedImages_(base.triangleCount()) {
  require(base.denseTriangle.size() == dense.vertexCount(), "dense sampler: the parametrisation does not match the mesh");
  require(dense.allFacesHave(3), "dense sampler: the dense mesh must be made of triangles");
  for (const auto& t : base.triangles) baseCorners_.push_back({base.positions[t[0]], base.positions[t[1]], base.positions[t[2]]});
  ownBase_.positions = base.positions;
  ownBase_.triangles = base.triangles;
  domain_ = std::make_unique<BaseDomain>(ownBase_);
  across_ = ownBase_.triangleNeighbours();
  const BaseDomain domain(base);  // with the parametrisation, which the copy above lacks
  // Each dense triangle through the one chart that holds its corners (as untangling sees it),
  // imaged in its corners' base triangles; when that chart is a base vertex's star the image may
  // cross the triangles between them, so it goes into the whole star. Corners in base triangles
  // that share no vertex (a long dense triangle) have no such chart: the other corners are brought
  // into each corner's triangle one triangle further (transferNear).
  BaseDomain::Chart chart;
  std::vector<std::uint32_t> homes;
  for (std::size_t f = 0; f < dense.faceCount(); ++f) {
    const auto c = dense.face(f);
    std::array<BaseDomain::Point2, 3> p;
    const bool charted = domain.chartDenseTriangle(c, chart, p);
    homes = {base.denseTriangle[c[0]], base.denseTriangle[c[1]], base.denseTriangle[c[2]]};
    if (charted && chart.vertex != BaseDomain::kNone) homes.insert(homes.end(), chart.star.begin(), chart.star.end());
    std::sort(homes.begin(), homes.end());
    homes.erase(std::unique(homes.begin(), homes.end()), homes.end());
    for (const std::uint32_t t : homes) {
      Image image{std::uint32_t(f), {}};
      bool ok = true;
      for (int i = 0; i < 3 && ok; ++i) {
        BaseDomain::Bary b;
        ok = charted ? domain.inFrame(chart, p[i], t, b) : domain.transferNear(base.denseTriangle[c[i]], base.denseBary[c[i]], t, b);
        image.uv[i] = {b[1], b[2]};
      }
      if (ok) (orient2(image.uv[0], image.uv[1], image.uv[2]) < 0 ? foldedImages_ : images_)[t].push_back(image);
    }
  }
  if (indexed)
    for (const auto& images : images_) grids_.push_back(makeGrid(images));
}

DenseSampler::ImageGrid DenseSampler::makeGrid(const std::vector<Image>& images) {
  ImageGrid g;
  if (images.size() < 8) return g;  // a scan is as quick
  // Boxes padded a little, so that a point a containment test holds (rounding included) lies in
  // every cell its image is listed in.
  constexpr double kPad = 1e-9;
  Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()}, hi = lo * -1;
  std::vector<std::array<Vec2, 2>> boxes;
  for (const Image& image : images) {
    std::array<Vec2, 2> box{image.uv[0], image.uv[0]};
    for (const Vec2& c : image.uv) {
      box[0] = {std::min(box[0].x, c.x), std::min(box[0].y, c.y)};
      box[1] = {std::max(box[1].x, c.x), std::max(box[1].y, c.y)};
    }
    box[0] = box[0] - Vec2{kPad, kPad};
    box[1] = box[1] + Vec2{kPad, kPad};
    lo = {std::min(lo.x, box[0].x), std::min(lo.y, box[0].y)};
    hi = {std::max(hi.x, box[1].x), std::max(hi.y, box[1].y)};
    boxes.push_back(box);
  }
  const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
  if (!(extent > 0) || !std::isfinite(extent)) return g;
  g.origin = lo;
  g.cells = std::clamp(int(std::sqrt(double(images.size()) * 2)), 1, 256);
  g.scale = g.cells / extent;
  // Two passes: count per cell, then place, so each cell lists its images in image order.
  std::vector<std::uint32_t> count(std::size_t(g.cells) * std::size_t(g.cells) + 1, 0);
  auto forCells = [&](const std::array<Vec2, 2>& box, auto&& visit) {
    for (int y = g.cellOf(box[0].y, lo.y); y <= g.cellOf(box[1].y, lo.y); ++y)
      for (int x = g.cellOf(box[0].x, lo.x); x <= g.cellOf(box[1].x, lo.x); ++x) visit(std::size_t(y * g.cells + x));
  };
  for (const auto& box : boxes) forCells(box, [&](std::size_t c) { ++count[c + 1]; });
  for (std::size_t c = 1; c < count.size(); ++c) count[c] += count[c - 1];
  g.start = count;
  g.items.resize(count.back());
  for (std::uint32_t i = 0; i < boxes.size(); ++i) forCells(boxes[i], [&](std::size_t c) { g.items[count[c]++] = i; });
  return g;
}

TriangleHit DenseSampler::findImage(std::uint32_t triangle, const Vec2& point) const {
  const std::vector<Image>& images = images_[triangle];
  TriangleHit hit;
  if (!grids_.empty() && grids_[triangle].cells > 0) {
    // The images listed in the point's cell hold every image that can hold the point; when none
    // does, the point lies outside them all and the scan below finds the nearest.
    const ImageGrid& g = grids_[triangle];
    const std::size_t cell = std::size_t(g.cellOf(point.y, g.origin.y) * g.cells + g.cellOf(point.x, g.origin.x));
    const std::uint32_t* listed = g.items.data() + g.start[cell];
    hit = locateInTriangles(point, g.start[cell + 1] - g.start[cell], [&](std::size_t i) { return images[listed[i]].uv; });
    if (hit.holds) hit.triangle = listed[hit.triangle];
  }
  ++queries_;
  if (!hit.holds) {
    ++fullScans_;
    hit = locateInTriangles(point, images.size(), [&](std::size_t i) { return images[i].uv; });
  }
  return hit;
}

DenseSampler::Hit DenseSampler::locate(std::uint32_t triangle, const std::array<double, 3>& bary) const {
  const Vec2 point{bary[1], bary[2]};
  TriangleHit hit = findImage(triangle, point);
  std::uint32_t from = triangle;
  // In a gap: the neighbours across the edges, nearest edge first.
  std::array<int, 3> edges{0, 1, 2};  // edge e runs from corner e to e + 1, opposite corner e + 2
  std::sort(edges.begin(), edges.end(), [&](int a, int b) { return bary[(a + 2) % 3] < bary[(b + 2) % 3]; });
  for (int k = 0; k < 3 && !hit.holds; ++k) {
    const std::uint32_t next = across_[triangle][edges[k]];
    BaseDomain::Bary moved;
    if (next == BaseMesh::kNoTriangle || !domain_->transfer(triangle, bary, next, moved)) continue;
    const TriangleHit there = findImage(next, {moved[1], moved[2]});
    if (there.holds) hit = there, from = next;
  }
  const std::vector<Image>& images = images_[from];
  Hit out;
  for (const Image& image : foldedImages_[triangle]) {
    const auto w = barycentric2(point, image.uv[0], image.uv[1], image.uv[2]);
    out.folded = out.folded || (w[0] >= 0 && w[1] >= 0 && w[2] >= 0);
  }
  if (hit.triangle == kNoTriangleHit) {
    out.bary = bary;
    return out;
  }
  // Outside every image (by rounding, or near a base vertex): the nearest one, clamped onto it.
  out.face = images[hit.triangle].denseFace;
  out.bary = hit.bary;
  out.held = hit.holds;
  return out;
}

Vec3 DenseSampler::hitPosition(std::uint32_t triangle, const Hit& hit) const {
  if (hit.face == kNoFace) {
    const auto& c = baseCorners_[triangle];
    return c[0] * hit.bary[0] + c[1] * hit.bary[1] + c[2] * hit.bary[2];
  }
  const auto c = dense_.face(hit.face);
  Vec3 p;
  for (int i = 0; i < 3; ++i) p = p + dense_.positions[c[i]] * hit.bary[i];
  return p;
}

Vec3 DenseSampler::position(std::uint32_t triangle, const std::array<double, 3>& bary) const {
  return hitPosition(triangle, locate(triangle, bary));
}

}  // namespace isoatlas::multires

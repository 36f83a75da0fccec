#include "viewer/tree_painting.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "edit/dvt/cpu_tree_passes.h"
#include "edit/solids/rasterise.h"
#include "edit/solids/volume_solid.h"

namespace isoatlas::viewer {

namespace dvt = edit::dvt;

TreePainting::TreePainting(const dvt::VolumeTree& tree, levelset::Backend backend, const dvt::TreeOptions& options) {
  auto passes = backend == levelset::Backend::Gpu ? dvt::makeGpuTreePasses() : dvt::makeCpuTreePasses();
  tree_ = std::make_unique<dvt::DynamicVolumeTree>(tree, std::move(passes), options);
  if (tree_->backend() != "gpu") upload();
}

void TreePainting::dabTo(const Vec3& centre, double radius, bool add) {
  const auto brush = last_ ? dvt::capsuleBrush(*last_, centre, radius) : dvt::sphereBrush(centre, radius);
  const dvt::TreeFrame& frame = tree_->frame();
  try {
    tree_->write(dvt::rasterise(*brush, frame, frame.voxelDepth()), add ? dvt::Op::Union : dvt::Op::Subtract);
  } catch (const Error&) {
    // A write past the node limit leaves the tree changed where it needed no new nodes: the picture
    // must be drawn from that tree, not from the streams uploaded before it (fewer nodes than nodeCount()).
    if (tree_->backend() != "gpu") upload();
    throw;
  }
  last_ = centre;
  ++dabs_;
  if (tree_->backend() != "gpu") upload();
}

void TreePainting::endStroke() {
  tree_->collapse();
  last_.reset();
  if (tree_->backend() != "gpu") upload();
}

dvt::GpuTreeBuffers TreePainting::buffers() const {
  if (tree_->backend() == "gpu") return dvt::gpuTreeBuffers(tree_->passes());
  return {pointers_->id(), cells_->id()};
}

void TreePainting::upload() {
  const dvt::VolumeTree t = tree_->tree();
  pointers_ = std::make_unique<gl::Buffer>(gl::Buffer::of(t.pointers));
  cells_ = std::make_unique<gl::Buffer>(gl::Buffer::of(t.cells));
}

std::optional<Vec3> pickTree(const dvt::VolumeTree& tree, const Vec3& origin, const Vec3& direction) {
  const dvt::TreeFrame& f = tree.frame;
  const double length = norm(direction);
  if (length == 0) return std::nullopt;
  const Vec3 d = direction * (1 / length);
  // The ray in voxel index coordinates (the direction is orthonormal, as a Volume's).
  auto toIndex = [&](const Vec3& p) {
    const Vec3 r = p - f.origin;
    return Vec3{dot(f.direction.column(0), r) / f.spacing.x, dot(f.direction.column(1), r) / f.spacing.y,
                dot(f.direction.column(2), r) / f.spacing.z};
  };
  // Clipped to the box of voxels -0.5 .. 2^K - 0.5 along each axis.
  const double side = double(f.voxelsPerAxis());
  const Vec3 o = toIndex(origin), e = toIndex(origin + d) - o;
  double t0 = 0, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    if (e[a] == 0) {
      if (o[a] < -0.5 || o[a] > side - 0.5) return std::nullopt;
      continue;
    }
    double lo = (-0.5 - o[a]) / e[a], hi = (side - 0.5 - o[a]) / e[a];
    if (lo > hi) std::swap(lo, hi);
    t0 = std::max(t0, lo), t1 = std::min(t1, hi);
  }
  const double step = 0.5 * std::min({f.spacing.x, f.spacing.y, f.spacing.z});
  for (double t = t0; t <= t1; t += step)
    if (dvt::sampleAt(tree, o + e * t).value > 0) return origin + d * t;
  return std::nullopt;
}

}  // namespace isoatlas::viewer

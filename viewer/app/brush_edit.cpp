#include "viewer/app/brush_edit.h"

#include "core/error.h"
#include "levelset/dvt/cpu_tree_passes.h"
#include "levelset/dvt/gpu_tree_passes.h"
#include "levelset/dvt/rasterise.h"
#include "levelset/dvt/volume_solid.h"

namespace isoatlas::viewer {

namespace dvt = levelset::dvt;

BrushResult brushSegmentation(const levelset::LevelSet& levelSet, const dvt::Solid& brush, dvt::Op op, gl::Context* gpu, int levels) {
  const dvt::TreeFrame frame = dvt::frameOf(levelSet.geometry());
  const std::uint32_t voxels = frame.voxelDepth();
  require(levels >= -int(voxels) && int(voxels) + levels <= int(dvt::kMaxDepth), "the brush's depth is past the tree's range");
  const std::uint32_t depth = std::uint32_t(int(voxels) + levels);
  BrushResult r;
  r.tree = std::make_unique<dvt::DynamicVolumeTree>(dvt::VolumeTree::empty(frame),
                                                    gpu ? dvt::makeGpuTreePasses(*gpu) : dvt::makeCpuTreePasses());
  r.tree->write(dvt::rasterise(dvt::VolumeSolid(levelSet), frame, voxels), dvt::Op::Union);
  r.tree->write(dvt::rasterise(brush, frame, depth), op);
  r.tree->collapse();
  r.mask = dvt::sampleMask(r.tree->tree(), levelSet.geometry().dims);
  return r;
}

}  // namespace isoatlas::viewer

#include "pipeline/segmentation_views.h"

#include "pipeline/gpu.h"
#include "pipeline/seed_ball.h"
#include "core/error.h"
#include "core/volume_io.h"
#include "levelset/level_set.h"
#include "render/orbit.h"
#include "render/slice_render.h"
#include "render/volume_render.h"

namespace isoatlas::pipeline {

Image renderSegmentationView(const SegmentationViewRequest& request, nlohmann::json& figures) {
  SegmentationViewRequest r = request;
  if (r.view.empty()) r.view = "slices";
  require(r.view == "slices" || r.view == "volume", "--view " + r.view + ": expected slices or volume for a volume");
  const bool clipped = r.clip != "off";
  require(!clipped || (r.clip.size() == 2 && (r.clip[0] == '+' || r.clip[0] == '-') && r.clip[1] >= 'x' && r.clip[1] <= 'z'),
          "--clip " + r.clip + ": expected +x, -x, +y, -y, +z, -z or off");
  require(r.opacity > 0 && r.opacity <= 1, "--opacity must lie in (0, 1]");
  const Volume volume = readVolume(r.volume);
  const Vec3 at = r.at.value_or(render::volumeCentre(volume));
  requireInside(volume, volume.worldToIndex(at), "--at");
  // The segmentation as a level set (CPU, no steps): its pages are what the window reads.
  levelset::LevelSet levelSet(volume, {}, {});
  std::int64_t inside = 0;
  if (!r.segmentation.empty()) {
    const Volume segmentation = readVolume(r.segmentation);
    require(segmentation.dims == volume.dims,
            r.segmentation + ": --segmentation needs the volume's voxel grid (" + std::to_string(volume.dims[0]) + " x " +
                std::to_string(volume.dims[1]) + " x " + std::to_string(volume.dims[2]) + ")");
    const Volume mask = isFloating(segmentation.type) ? levelset::maskOf(segmentation) : segmentation;
    levelSet.setMask(mask);
    for (std::size_t n = 0; n < mask.voxelCount(); ++n) inside += mask.value(n) > 0;
  }
  const render::IntensityWindow window = render::percentileWindow(volume, 1, 99.5);
  figures["view"] = r.view;
  figures["inside_voxels"] = inside;

  Gpu gpu;  // the process's one context, for the volume rendering
  if (r.view == "slices") {
    const int panel = std::max(16, std::min(r.width / 3, r.height));
    render::SliceOptions o{.panelSize = panel, .window = window, .crosshair = true};
    if (!r.segmentation.empty()) o.phi = render::pagedField(levelSet);
    figures["size"] = {3 * panel, panel};
    return render::renderSlices(volume, at, o);
  }
  gpu.needGl();
  render::VolumeRenderView view{.camera = r.camera.value_or(render::Orbit{}.camera(render::gridBounds(volume), r.width, r.height)),
                                .window = window,
                                .opacity = r.opacity,
                                .insideOnly = r.insideOnly,
                                .surface = !r.segmentation.empty()};
  if (clipped) {
    Vec3 normal{0, 0, 0};
    normal[r.clip[1] - 'x'] = r.clip[0] == '+' ? 1 : -1;
    view.clip = render::ClipPlane{at, normal};
  }
  figures["size"] = {r.width, r.height};
  return render::renderVolume(volume, levelSet, view);
}

}  // namespace isoatlas::pipeline

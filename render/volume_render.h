// VolumeRenderer: GPU ray casting of a scan and of a level set straight from the level set's packed
// pages (Lefohn's thesis, sec. 3.4: the page table finds each page of phi in the pool, nothing is
// unpacked into a dense phi; levelset/paged_phi_gpu.h), in a compute shader (shaders/volume_raycast.comp)
// whose picture is copied into the bound framebuffer. The caller owns the GL context.
//   the scan: a transfer function (the intensity window as a grey ramp, opacity rising with it),
//     everywhere or only inside the level set (the level set as a region of interest);
//   the level set: its zero set as a lit surface;
//   a clipping plane: its positive side cut away; the cut face shows the scan, the level set's inside
//     tinted and its contour where the plane cuts the surface.
#pragma once
#include <array>
#include <optional>

#include "core/gl/context.h"
#include "core/image.h"
#include "core/volume.h"
#include "levelset/level_set.h"
#include "levelset/paged_phi_gpu.h"
#include "render/camera.h"
#include "render/slice_render.h"

namespace isoatlas::render {

struct ClipPlane {
  Vec3 point, normal;  // world; the side the normal points to is cut away
};

struct VolumeRenderView {
  Camera camera;
  IntensityWindow window;
  double opacity = 0.08;     // per voxel of path, at the window's top
  bool scan = true;          // the scan through the transfer function
  bool insideOnly = false;   // the scan only inside the level set
  bool surface = true;       // the level set's zero set
  std::optional<ClipPlane> clip;
  Vec3 colour{0.93, 0.78, 0.62}, background{1, 1, 1};
};

class VolumeRenderer {
public:
  VolumeRenderer();  // in gl::Context::current(), as every renderer of render/
  // The scan, uploaded once (float, linear filtering); its grid is the level set's.
  void setSource(const Volume& source);
  // Draws into the bound framebuffer (of the camera's size).
  void draw(const levelset::PagedPhiGpu& phi, const VolumeRenderView& view);

private:
  Volume geometry_;  // the scan's grid, no voxels
  gl::Texture source_;
  std::unique_ptr<gl::Framebuffer> rays_;
};

// The world box around a volume's voxels (their outer faces, not their centres).
Box gridBounds(const Volume& volume);

// A picture of a level set and its scan, drawn offscreen in the current context and read back.
Image renderVolume(const Volume& source, const levelset::LevelSet& levelSet, const VolumeRenderView& view);

}  // namespace isoatlas::render

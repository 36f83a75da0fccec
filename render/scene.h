// Scene: models placed as instances and drawn through the cascade: per instance a CPU level (the
// same level everywhere, lowered with the instance's distance in a grid, or an error on the screen)
// and its patch list on the GPU, updated where it changed; then one tessellated draw of them all.
//   grid(n)   n x n instances on the ground plane (z up), the models in turn, a model's width apart
//   refine()  the CPU stage for a camera; draw items for AtlasRenderer
#pragma once
#include <map>
#include <memory>
#include <vector>

#include "render/atlas_render.h"
#include "render/model_lod.h"
#include "render/smooth_render.h"

namespace isoatlas::render {

struct Instance {
  std::size_t model = 0;
  Vec3 offset{0, 0, 0};
  int cpuLevel = 0;  // the level it was refined to (Level mode)
};

struct SceneCpuFigures {
  double ms = 0;                 // refinement and patch lists
  std::size_t uploadBytes = 0;   // patch lists sent to the GPU
  std::size_t cpuFaces = 0;      // the CPU meshes' triangles, over the instances
  std::size_t splits = 0, welds = 0;  // this frame's, over the instances
  int minLevel = 0, maxLevel = 0;  // over the instances (Level mode)
};

class Scene {
public:
  // Uploads each model's atlas (current GL context); the models must outlive the scene.
  explicit Scene(const std::vector<const atlas::Model*>& models);
  void grid(int n);  // replaces the single instance of model 0 the scene starts with
  const std::vector<Instance>& instances() const { return instances_; }
  std::vector<Vec3> offsets() const;  // the instances' placements
  Box bounds() const;
  // Model 0 seen from the front, or the grid from the front and above, whole on the image.
  Camera defaultCamera(int width, int height) const;
  SceneCpuFigures refine(const CpuRefinement& cpu, const Camera& camera);
  std::vector<DrawItem> items() const;
  const AtlasTextures& textures(std::size_t model) const { return *models_.at(model).textures; }

private:
  struct Entry {
    const atlas::Model* model;
    std::unique_ptr<ModelLod> lod;
    std::unique_ptr<AtlasTextures> textures;
    Box box;
  };
  std::vector<Entry> models_;
  std::vector<Instance> instances_;
  bool grid_ = false;
  // Patch lists: per (model, level) in Level mode, shared by the instances at that level; per
  // instance in Pixels mode, beside the instance's CPU mesh, which each frame adapts.
  struct Cached {
    PatchBuffer patches;
    std::size_t cpuFaces = 0;
  };
  std::map<std::pair<std::size_t, int>, Cached> byLevel_;
  std::vector<PatchBuffer> byInstance_;
  std::vector<multires::AdaptiveMesh> meshes_;
  std::vector<const PatchBuffer*> drawn_;
};

struct FrameReport {
  SceneCpuFigures cpu;
  FrameFigures gpu;
  double ms = 0;  // the whole frame: CPU stage, uploads, draw, finish
};
// One frame of the cascade: the scene refined for the camera, drawn into `target`.
FrameReport drawFrame(Scene& scene, const AtlasRenderer& renderer, const CpuRefinement& cpu, const GpuRefinement& gpu,
                      const Camera& camera, const DrawStyle& style, const gl::Framebuffer& target);
// One frame of the smooth mode: OpenSubdiv's limit surface of every instance at level T, with the
// atlas's detail when `displaced` (no CPU stage).
FrameReport drawSmoothFrame(const Scene& scene, const SmoothSurface& smooth, int level, bool displaced, const Camera& camera,
                            const DrawStyle& style, const gl::Framebuffer& target);

}  // namespace isoatlas::render

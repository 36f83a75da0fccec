#include "render/scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/error.h"

namespace isoatlas::render {

Scene::Scene(const std::vector<const atlas::Model*>& models) {
  require(!models.empty(), "no model to render");
  for (const atlas::Model* m : models)
    models_.push_back({m, std::make_unique<ModelLod>(*m), std::make_unique<AtlasTextures>(m->atlas), boundingBox(m->base.positions)});
  instances_ = {Instance{}};
}

void Scene::grid(int n) {
  meshes_.clear();
  require(n >= 1 && n <= 64, "--scene grid:NxN takes N from 1 to 64");
  double spacing = 0;
  for (const Entry& e : models_) spacing = std::max({spacing, e.box.max.x - e.box.min.x, e.box.max.y - e.box.min.y});
  spacing *= 1.2;
  instances_.clear();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::size_t m = std::size_t(j * n + i) % models_.size();
      const Box& b = models_[m].box;
      const Vec3 centre{(b.min.x + b.max.x) / 2, (b.min.y + b.max.y) / 2, b.min.z};
      instances_.push_back({m, Vec3{(i - (n - 1) / 2.0) * spacing, (j - (n - 1) / 2.0) * spacing, 0} - centre, 0});
    }
  grid_ = true;
}

std::vector<Vec3> Scene::offsets() const {
  std::vector<Vec3> out;
  for (const Instance& i : instances_) out.push_back(i.offset);
  return out;
}

Box Scene::bounds() const {
  Box out{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
  for (const Instance& i : instances_) {
    const Box& b = models_[i.model].box;
    for (int a = 0; a < 3; ++a) {
      out.min[a] = std::min(out.min[a], b.min[a] + i.offset[a]);
      out.max[a] = std::max(out.max[a], b.max[a] + i.offset[a]);
    }
  }
  return out;
}

Camera Scene::defaultCamera(int width, int height) const {
  if (!grid_) return Camera::framing(bounds(), width, height);
  // Low over the front row, looking across the grid: the near instances fill the picture, the far
  // ones shrink towards the horizon (the paper's Fig. 9).
  const Box b = bounds();
  const double depth = b.max.y - b.min.y, cx = (b.min.x + b.max.x) / 2;
  Camera c;
  c.width = width, c.height = height;
  c.fovDegrees = 50;
  c.eye = {cx, b.min.y - 0.25 * depth, b.max.z + 0.3 * depth};
  c.target = {cx, b.min.y + 0.45 * depth, b.min.z};
  return c;
}

SceneCpuFigures Scene::refine(const CpuRefinement& cpu, const Camera& camera) {
  const auto start = std::chrono::steady_clock::now();
  SceneCpuFigures f;
  drawn_.assign(instances_.size(), nullptr);
  if (cpu.mode == CpuRefinement::Mode::Level) {
    // The nearest instance gets the level asked for; twice as far, one halving (two levels) less.
    double nearest = 1e300;
    std::vector<double> distance;
    for (const Instance& i : instances_) {
      const Box& b = models_[i.model].box;
      distance.push_back(norm((b.min + b.max) * 0.5 + i.offset - camera.eye));
      nearest = std::min(nearest, distance.back());
    }
    f.minLevel = cpu.level;
    for (std::size_t k = 0; k < instances_.size(); ++k) {
      Instance& i = instances_[k];
      const int drop = grid_ ? int(std::lround(2 * std::log2(std::max(distance[k] / nearest, 1.0)))) : 0;
      i.cpuLevel = std::max(0, cpu.level - drop);
      f.minLevel = std::min(f.minLevel, i.cpuLevel);
      const auto key = std::make_pair(i.model, i.cpuLevel);
      auto found = byLevel_.find(key);
      if (found == byLevel_.end()) {
        CpuFigures c;
        const auto patches = models_[i.model].lod->patches({CpuRefinement::Mode::Level, i.cpuLevel}, camera, i.offset, &c);
        found = byLevel_.emplace(key, Cached()).first;
        f.uploadBytes += found->second.patches.update(patches);
        found->second.cpuFaces = c.faces;
      }
      f.cpuFaces += found->second.cpuFaces;
      drawn_[k] = &found->second.patches;
    }
    f.maxLevel = cpu.level;
  } else {
    byInstance_.resize(instances_.size());
    while (meshes_.size() < instances_.size()) meshes_.push_back(models_[instances_[meshes_.size()].model].lod->start());
    for (std::size_t k = 0; k < instances_.size(); ++k) {
      const Instance& i = instances_[k];
      const ModelLod& lod = *models_[i.model].lod;
      const CpuFigures c = lod.adapt(meshes_[k], cpu, camera, i.offset);
      if (c.splits + c.welds > 0 || byInstance_[k].count() == 0) f.uploadBytes += byInstance_[k].update(lod.patchesOf(meshes_[k]));
      f.cpuFaces += c.faces;
      f.splits += c.splits, f.welds += c.welds;
      drawn_[k] = &byInstance_[k];
    }
  }
  f.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return f;
}

std::vector<DrawItem> Scene::items() const {
  std::vector<DrawItem> out;
  for (std::size_t k = 0; k < instances_.size(); ++k)
    if (drawn_.size() == instances_.size() && drawn_[k]) out.push_back({models_[instances_[k].model].textures.get(), drawn_[k], instances_[k].offset});
  return out;
}

FrameReport drawFrame(Scene& scene, const AtlasRenderer& renderer, const CpuRefinement& cpu, const GpuRefinement& gpu,
                      const Camera& camera, const DrawStyle& style, const gl::Framebuffer& target) {
  const auto start = std::chrono::steady_clock::now();
  FrameReport f;
  f.cpu = scene.refine(cpu, camera);
  f.gpu = renderer.draw(scene.items(), camera, scene.bounds(), gpu, style, target);  // ends with glFinish
  f.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return f;
}

FrameReport drawSmoothFrame(const Scene& scene, const SmoothSurface& smooth, int level, bool displaced, const Camera& camera,
                            const DrawStyle& style, const gl::Framebuffer& target) {
  const auto start = std::chrono::steady_clock::now();
  FrameReport f;
  f.gpu = smooth.draw(scene.offsets(), camera, scene.bounds(), level, displaced, style, target);
  f.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return f;
}

}  // namespace isoatlas::render

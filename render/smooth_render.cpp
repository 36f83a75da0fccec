// The one file that includes OpenSubdiv (Far and Osd's shader sources).
#include "render/smooth_render.h"

#include <epoxy/gl.h>  // before OpenSubdiv's headers, which would include <GL/gl.h>

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/osd/cpuPatchTable.h>
#include <opensubdiv/osd/glslPatchShaderSource.h>

#include <algorithm>
#include <deque>

#include "core/error.h"
#include "core/gl/context.h"
#include "kRenderShaders.h"

namespace isoatlas::render {
namespace {

using namespace OpenSubdiv;

// A control point as Far's stencils interpolate it.
struct ControlPoint {
  float p[3];
  void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0; }
  void AddWithWeight(const ControlPoint& source, float weight) {
    for (int i = 0; i < 3; ++i) p[i] += weight * source.p[i];
  }
};

// Our shaders and OpenSubdiv's generated ones (as osd/*), in one table for the shader library.
const gl::EmbeddedShader* smoothShaders() {
  static const std::vector<gl::EmbeddedShader> table = [] {
    static std::deque<std::string> texts;  // stable addresses
    std::vector<gl::EmbeddedShader> t;
    for (const gl::EmbeddedShader* s = gl::kRenderShaders; s->path; ++s) t.push_back(*s);
    auto add = [&](const char* path, std::string text) {
      texts.push_back(std::move(text));
      t.push_back({path, texts.back().c_str()});
    };
    using Source = Osd::GLSLPatchShaderSource;
    add("osd/common.glsl", Source::GetCommonShaderSource());
    for (const auto& [name, type] : {std::pair{"regular", Far::PatchDescriptor::REGULAR}, std::pair{"gregory", Far::PatchDescriptor::GREGORY_BASIS}}) {
      const std::string n = name;
      static std::deque<std::string> paths;
      paths.push_back("osd/" + n + ".vert");
      add(paths.back().c_str(), Source::GetVertexShaderSource(type));
      paths.push_back("osd/" + n + ".tesc");
      add(paths.back().c_str(), Source::GetTessControlShaderSource(type));
      paths.push_back("osd/" + n + ".tese");
      add(paths.back().c_str(), Source::GetTessEvalShaderSource(type));
    }
    t.push_back({nullptr, nullptr});
    return t;
  }();
  return table.data();
}

// A patch type's program: with our geometry stage (wireframe, transform feedback), or `direct` to
// the fragments.
const gl::Program& programFor(int type, bool direct) {
  const std::string name = type == Far::PatchDescriptor::REGULAR ? "regular" : "gregory";
  const std::string stem = "render/shaders/smooth_" + name;
  std::vector<std::string> paths = {stem + ".vert", stem + ".tesc", stem + ".tese"};
  if (direct) {
    paths.push_back("render/shaders/smooth_direct.frag");
    return gl::Context::current().program({smoothShaders(), paths, {}, {}});
  }
  paths.insert(paths.end(), {"render/shaders/smooth.geom", "render/shaders/atlas.frag"});
  return gl::Context::current().program({smoothShaders(), paths, {}, {"worldPosition"}});
}

constexpr int kTypes[] = {Far::PatchDescriptor::REGULAR, Far::PatchDescriptor::GREGORY_BASIS};

}  // namespace

SmoothSurface::SmoothSurface(const atlas::Model& model, const AtlasTextures& textures, int isolation) : textures_(&textures) {
  require(isolation >= 1 && isolation <= 6, "the smooth mode's isolation level must lie between 1 and 6");
  const Mesh cage = model.base.quadMesh();  // face i: tile i's corners p, s, q, r
  faces_ = cage.faceCount();
  std::vector<int> counts(faces_, 4), corners(cage.faceVertices.begin(), cage.faceVertices.end());
  Far::TopologyDescriptor d;
  d.numVertices = int(cage.vertexCount());
  d.numFaces = int(faces_);
  d.numVertsPerFace = counts.data();
  d.vertIndicesPerFace = corners.data();
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  std::unique_ptr<Far::TopologyRefiner> refiner(Far::TopologyRefinerFactory<Far::TopologyDescriptor>::Create(
      d, Far::TopologyRefinerFactory<Far::TopologyDescriptor>::Options(Sdc::SCHEME_CATMARK, sdc)));
  require(refiner != nullptr, "OpenSubdiv refused the base mesh as a Catmull-Clark cage");
  Far::PatchTableFactory::Options options(isolation);
  options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
  options.useInfSharpPatch = true;
  refiner->RefineAdaptive(options.GetRefineAdaptiveOptions());
  const std::unique_ptr<Far::PatchTable> table(Far::PatchTableFactory::Create(*refiner, options));

  // Control points: the cage's, then every refined level's and the end caps' local points, all
  // from the cage by stencils.
  // (The float-typed Real<float> classes directly: the StencilTable wrappers downcast their base
  // class objects, which UBSan rightly reports.)
  using Stencils = Far::StencilTableReal<float>;
  using StencilFactory = Far::StencilTableFactoryReal<float>;
  StencilFactory::Options stencilOptions;
  stencilOptions.generateOffsets = true;
  stencilOptions.generateIntermediateLevels = true;
  std::unique_ptr<const Stencils> stencils(StencilFactory::Create(*refiner, stencilOptions));
  if (const Stencils* local = table->GetLocalPointStencilTable<float>())
    if (const Stencils* all = StencilFactory::AppendLocalPointStencilTable(*refiner, stencils.get(), local))
      stencils.reset(all);
  std::vector<ControlPoint> points(cage.vertexCount() + std::size_t(stencils->GetNumStencils()));
  for (std::size_t v = 0; v < cage.vertexCount(); ++v)
    points[v] = {{float(cage.positions[v].x), float(cage.positions[v].y), float(cage.positions[v].z)}};
  if (stencils->GetNumStencils() > 0) stencils->UpdateValues(points.data(), points.data() + cage.vertexCount());

  const std::unique_ptr<Osd::CpuPatchTable> cpu(Osd::CpuPatchTable::Create(table.get()));
  controlVertices_ = gl::Buffer::of(points);
  indices_ = gl::Buffer(cpu->GetPatchIndexSize() * sizeof(int), cpu->GetPatchIndexBuffer());
  patchParams_ = gl::Buffer(cpu->GetPatchParamSize() * sizeof(Osd::PatchParam), cpu->GetPatchParamBuffer());
  static_assert(sizeof(Osd::PatchParam) == 3 * sizeof(int), "the shaders read a patch's parameters as three ints");
  patchParamTexture_ = gl::Texture::textureBuffer(GL_RGB32I, patchParams_);
  for (std::size_t a = 0; a < cpu->GetNumPatchArrays(); ++a) {
    const Osd::PatchArray& array = cpu->GetPatchArrayBuffer()[a];
    const int type = array.GetPatchType();
    require(type == Far::PatchDescriptor::REGULAR || type == Far::PatchDescriptor::GREGORY_BASIS,
            "OpenSubdiv made patches of a kind the smooth mode does not draw");
    arrays_.push_back({type, array.GetDescriptor().GetNumControlVertices(), array.GetNumPatches(), array.GetIndexBase(),
                       array.GetPrimitiveIdBase()});
    patches_ += std::size_t(array.GetNumPatches());
  }
  glVertexArrayVertexBuffer(vao_.id(), 0, controlVertices_.id(), 0, sizeof(ControlPoint));
  glEnableVertexArrayAttrib(vao_.id(), 0);
  glVertexArrayAttribFormat(vao_.id(), 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_.id(), 0, 0);
  glVertexArrayElementBuffer(vao_.id(), indices_.id());
  chunked_ = gl::Context::current().info().software();
  gl::checkErrors("uploading the smooth surface");
}

SmoothSurface::~SmoothSurface() = default;

void SmoothSurface::setUniforms(const Camera& camera, const Box& scene, int tessLevel, bool displaced, const DrawStyle& style) const {
  camera.check();
  require(tessLevel >= 1 && tessLevel <= 64, "the smooth mode's tessellation level must lie between 1 and 64");
  const auto range = depthRange(camera, scene);
  const auto vp = camera.viewProjection(range[0], range[1]);
  const atlas::AtlasLayout& layout = textures_->layout();
  for (const int type : kTypes)
    for (const bool direct : {false, true}) {
      const GLuint p = programFor(type, direct).id();
      auto at = [p](const char* name) { return glGetUniformLocation(p, name); };
      glProgramUniformMatrix4fv(p, at("viewProjection"), 1, GL_FALSE, vp.data());
      glProgramUniform2f(p, at("viewport"), float(camera.width), float(camera.height));
      glProgramUniform1f(p, at("tessLevel"), float(tessLevel));
      glProgramUniform1i(p, at("displace"), displaced);
      glProgramUniform1ui(p, at("chartSize"), layout.chartSize);
      glProgramUniform1ui(p, at("atlasColumns"), layout.columns);
      glProgramUniform1i(p, at("OsdPatchParamBuffer"), 4);
      glProgramUniform3f(p, at("eye"), float(camera.eye.x), float(camera.eye.y), float(camera.eye.z));
      glProgramUniform3f(p, at("colour"), float(style.colour.x), float(style.colour.y), float(style.colour.z));
      glProgramUniform1i(p, at("colourByChart"), style.colourByChart);
      glProgramUniform1i(p, at("wireframe"), style.wireframe);
    }
  glBindTextureUnit(0, textures_->positions().id());
  glBindTextureUnit(1, textures_->normals().id());
  glBindTextureUnit(4, patchParamTexture_.id());
  vao_.bind();
}

void SmoothSurface::drawArrays(const std::vector<Vec3>& offsets, int type, bool direct) const {
  for (const Vec3& offset : offsets)
    for (const PatchArray& array : arrays_) {
      if (type >= 0 && array.type != type) continue;
      const gl::Program& p = programFor(array.type, direct);
      GLint current = 0;
      glGetIntegerv(GL_CURRENT_PROGRAM, &current);
      if (GLuint(current) != p.id()) p.use();
      const float model[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, float(offset.x), float(offset.y), float(offset.z), 1};
      glUniformMatrix4fv(p.uniform("model"), 1, GL_FALSE, model);
      glPatchParameteri(GL_PATCH_VERTICES, array.controlVertices);
      const int chunk = chunked_ ? std::max(1, 1024 / array.controlVertices) : array.patches;
      for (int first = 0; first < array.patches; first += chunk) {
        const int count = std::min(chunk, array.patches - first);
        glUniform1i(p.uniform("PrimitiveIdBase"), array.primitiveIdBase + first);
        glDrawElements(GL_PATCHES, count * array.controlVertices, GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(std::uintptr_t(array.indexBase + first * array.controlVertices) * sizeof(int)));
      }
    }
  gl::checkErrors("drawing the smooth surface");
}

FrameFigures SmoothSurface::draw(const std::vector<Vec3>& offsets, const Camera& camera, const Box& scene, int tessLevel,
                                 bool displaced, const DrawStyle& style, const gl::Framebuffer& target) const {
  FrameFigures f = drawMeasured(target, style.background, [&] {
    setUniforms(camera, scene, tessLevel, displaced, style);
    drawArrays(offsets, -1, !style.wireframe);
  });
  f.patches = patches_ * offsets.size();
  return f;
}

Mesh SmoothSurface::capture(const std::vector<Vec3>& offsets, const Camera& camera, const Box& scene, int tessLevel,
                            bool displaced) const {
  setUniforms(camera, scene, tessLevel, displaced, {});
  std::vector<CapturePass> passes;
  for (const int type : kTypes) passes.push_back({&programFor(type, false), [this, &offsets, type] { drawArrays(offsets, type, false); }});
  return captureTriangles(passes);
}

}  // namespace isoatlas::render

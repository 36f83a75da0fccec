#include "viewer/app/viewer_app.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE  // epoxy declares GL
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>

#include "atlas/model_file.h"
#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/resources.h"
#include "core/gz_file.h"
#include "core/image.h"
#include "core/volume_io.h"
#include "levelset/dvt/dvt_file.h"
#include "viewer/dvt_render.h"
#include "viewer/scene.h"
#include "viewer/slice_render.h"

namespace isoatlas::viewer {
namespace {

// The camera orbiting a box: angles about its centre, distance in its diagonals.
struct Orbit {
  double yaw = -1.57, pitch = 0.25, distance = 1.6;
  Camera camera(const Box& box, int width, int height) const {
    const Vec3 centre = (box.min + box.max) * 0.5;
    const double r = distance * std::max(box.diagonal(), 1e-6);
    Camera c;
    c.target = centre;
    c.eye = centre + Vec3{std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch)} * r;
    c.width = width, c.height = height;
    return c;
  }
  void drag(double dx, double dy) {
    yaw -= dx * 0.01;
    pitch = std::clamp(pitch + dy * 0.01, -1.5, 1.5);
  }
};

// What the window shows: one of these, from the file's kind.
struct ModelView {
  atlas::Model model;
  std::unique_ptr<Scene> scene;
  std::unique_ptr<AtlasRenderer> renderer;
  int cpuLevel = 2, gpuHalvings = 1;
  bool wire = false, chartColours = false;
};
struct TreeView {
  levelset::dvt::VolumeTree tree;
  std::unique_ptr<gl::Buffer> pointers, cells;
  std::unique_ptr<DvtRenderer> renderer;
  Box box;
  bool cubes = false;
};
struct VolumeView {
  Volume volume;
  Vec3 point;
  std::unique_ptr<gl::Texture> slices;
  int width = 0, height = 0;
  bool dirty = true;
};

void requireDisplay() {
  const char* x = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((!x || !*x) && (!wayland || !*wayland))
    throw Error("isoatlas view needs a display (DISPLAY is not set): run it on a desktop, or under xvfb-run; "
                "`isoatlas render` and `isoatlas edit --render` make the same pictures headless");
}

void uploadSlices(VolumeView& v) {
  const Image img = renderSlices(v.volume, v.point);
  std::vector<unsigned char> rgba(std::size_t(img.width) * img.height * 4, 255);
  for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i)
    for (int c = 0; c < 3; ++c) rgba[4 * i + c] = img.pixels[3 * i + c];
  v.slices = std::make_unique<gl::Texture>(gl::Texture::texture2D(GL_RGBA8, img.width, img.height));
  glTextureSubImage2D(v.slices->id(), 0, 0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  v.width = img.width, v.height = img.height;
  v.dirty = false;
}

}  // namespace

void runViewer(const ViewerOptions& options) {
  require(options.files.size() == 1, "isoatlas view takes one file (a model, a volume tree or a volume)");
  require(options.frames >= 0, "--frames must be >= 0");
  require(options.screenshot.empty() || endsWith(options.screenshot, ".png"), options.screenshot + ": --screenshot writes a PNG");
  const std::string& file = options.files.front();
  // Read before any window opens, so a bad file is one line.
  std::optional<ModelView> model;
  std::optional<TreeView> tree;
  std::optional<VolumeView> volume;
  if (endsWith(file, ".isoatlas")) {
    model.emplace();
    model->model = atlas::readModel(file);
  } else if (endsWith(file, ".dvt")) {
    tree.emplace();
    tree->tree = levelset::dvt::readDvt(file);
    tree->box = insideBounds(tree->tree);
  } else {
    volume.emplace();
    volume->volume = readVolume(file);
    volume->point = volumeCentre(volume->volume);
  }
  requireDisplay();

  auto context = gl::Context::window(options.width, options.height, "isoatlas view - " + file);
  GLFWwindow* window = context->glfwWindow();
  glfwSwapInterval(options.frames > 0 ? 0 : 1);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the user's files
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 450");

  if (model) {
    model->scene = std::make_unique<Scene>(std::vector<const atlas::Model*>{&model->model});
    model->renderer = std::make_unique<AtlasRenderer>();
  }
  if (tree) {
    tree->pointers = std::make_unique<gl::Buffer>(gl::Buffer::of(tree->tree.pointers));
    tree->cells = std::make_unique<gl::Buffer>(gl::Buffer::of(tree->tree.cells));
    tree->renderer = std::make_unique<DvtRenderer>(*context);
  }
  Orbit orbit;
  double lastX = 0, lastY = 0;
  std::unique_ptr<gl::Framebuffer> target;
  int shots = 0;
  bool pWasDown = false;
  for (int frame = 0; !glfwWindowShouldClose(window); ++frame) {
    glfwPollEvents();
    int width = 0, height = 0;
    glfwGetFramebufferSize(window, &width, &height);
    width = std::max(width, 1), height = std::max(height, 1);
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    // Orbit and zoom with the mouse where no panel takes it.
    double x = 0, y = 0;
    glfwGetCursorPos(window, &x, &y);
    const ImGuiIO& io = ImGui::GetIO();
    if (!io.WantCaptureMouse) {
      if (glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) orbit.drag(x - lastX, y - lastY);
      if (io.MouseWheel != 0) orbit.distance = std::clamp(orbit.distance * std::pow(0.9, io.MouseWheel), 0.05, 20.0);
    }
    lastX = x, lastY = y;

    ImGui::Begin("isoatlas");
    ImGui::TextUnformatted(file.c_str());
    if (model) {
      ImGui::SliderInt("CPU level", &model->cpuLevel, 0, 8);
      ImGui::SliderInt("GPU halvings", &model->gpuHalvings, 0, 4);
      ImGui::Checkbox("wireframe", &model->wire);
      ImGui::Checkbox("chart colours", &model->chartColours);
    }
    if (tree) {
      ImGui::Text("%zu nodes, %zu leaves, depth %u", tree->tree.nodeCount(), tree->tree.leafCount(), tree->tree.maxDepth());
      ImGui::Checkbox("cubes (else ray cast)", &tree->cubes);
    }
    if (volume) {
      float p[3] = {float(volume->point.x), float(volume->point.y), float(volume->point.z)};
      const Vec3 lo = volume->volume.indexToWorld({0, 0, 0});
      const Vec3 hi = volume->volume.indexToWorld({double(volume->volume.dims[0] - 1), double(volume->volume.dims[1] - 1),
                                                    double(volume->volume.dims[2] - 1)});
      const char* names[3] = {"x (mm)", "y (mm)", "z (mm)"};
      for (int a = 0; a < 3; ++a)
        if (ImGui::SliderFloat(names[a], &p[a], float(std::min(lo[a], hi[a])), float(std::max(lo[a], hi[a])))) volume->dirty = true;
      volume->point = {p[0], p[1], p[2]};
    }
    ImGui::Text("%.1f ms a frame", 1000.0 / std::max(1.0f, io.Framerate));
    const bool pDown = glfwGetKey(window, GLFW_KEY_P) == GLFW_PRESS;
    const bool shoot = ImGui::Button("screenshot (P)") || (!io.WantCaptureKeyboard && pDown && !pWasDown);
    pWasDown = pDown;
    ImGui::End();

    if (!target || target->width() != width || target->height() != height) target = std::make_unique<gl::Framebuffer>(width, height);
    if (model) {
      const Camera cam = orbit.camera(model->scene->bounds(), width, height);
      drawFrame(*model->scene, *model->renderer, {.mode = CpuRefinement::Mode::Level, .level = model->cpuLevel},
                {.mode = GpuRefinement::Mode::Level, .halvings = model->gpuHalvings}, cam,
                {.wireframe = model->wire, .colourByChart = model->chartColours}, *target);
    } else if (tree) {
      target->bind();
      tree->renderer->draw({tree->pointers->id(), tree->cells->id()}, tree->tree.nodeCount(), tree->tree.frame,
                           {.camera = orbit.camera(tree->box, width, height),
                            .mode = tree->cubes ? DvtRenderMode::Cubes : DvtRenderMode::RayCast});
    } else {
      target->bind();
      glViewport(0, 0, width, height);
      glClearColor(1, 1, 1, 1);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      if (volume->dirty) uploadSlices(*volume);
      ImGui::SetNextWindowPos(ImVec2(float(width) * 0.3f, 10), ImGuiCond_FirstUseEver);
      ImGui::Begin("slices");
      const float scale = std::min(1.0f, (float(width) * 0.65f) / float(volume->width));
      ImGui::Image(ImTextureID(std::intptr_t(volume->slices->id())), ImVec2(float(volume->width) * scale, float(volume->height) * scale));
      ImGui::End();
    }
    glBlitNamedFramebuffer(target->id(), 0, 0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    const bool last = options.frames > 0 && frame + 1 >= options.frames;
    if (shoot) writePng("isoatlas_view_" + std::to_string(shots++) + ".png", gl::readWindowImage(width, height));
    if (last && !options.screenshot.empty()) writePng(options.screenshot, gl::readWindowImage(width, height));
    glfwSwapBuffers(window);
    if (last) break;
  }
  target.reset();
  model.reset();
  tree.reset();
  volume.reset();
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

}  // namespace isoatlas::viewer

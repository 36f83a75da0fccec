#include "viewer/viewer_app.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE  // epoxy declares GL
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <optional>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/resources.h"
#include "core/gz_file.h"
#include "core/image.h"
#include "core/text.h"
#include "viewer/view_script.h"
#include "viewer/viewer_state.h"

namespace isoatlas::viewer {
namespace {

using window::Viewer;

void requireDisplay() {
  const char* x = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((!x || !*x) && (!wayland || !*wayland))
    throw Error("isoatlas view needs a display (DISPLAY is not set): run it on a desktop, or under xvfb-run; "
                "`isoatlas render` and `isoatlas edit --render` make the same pictures headless");
}

// Dear ImGui over the window, torn down however the loop ends.
struct ImGuiScope {
  explicit ImGuiScope(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the user's files
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 450");
  }
  ~ImGuiScope() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
};

}  // namespace

int slicePanelSize(int width, int height) { return std::max(16, std::min((width - kControlsWidth) / 3, height / 2)); }

ViewerReport runViewer(const ViewerOptions& options) {
  require(options.frames >= 0, "--frames must be >= 0");
  require(options.screenshot.empty() || endsWith(options.screenshot, ".png"), options.screenshot + ": --screenshot writes a PNG");
  // Read before any window opens, so a bad file or script is one line.
  std::vector<window::Loaded> files;
  for (const std::string& f : options.files) files.push_back(window::load(f, options.read));
  std::optional<ScriptPlayer> script;
  if (!options.script.empty()) script.emplace(readViewScript(options.script));
  requireDisplay();

  auto context = gl::Context::window(options.width, options.height, "isoatlas view");
  GLFWwindow* window = context->glfwWindow();
  glfwSwapInterval(options.frames > 0 || script ? 0 : 1);
  ImGuiScope imgui(window);
  ViewerReport report;
  {
    Viewer viewer(options);
    for (window::Loaded& l : files) viewer.show(std::move(l));
    int shots = 0;
    bool pWasDown = false;
    auto last = std::chrono::steady_clock::now();
    for (int frame = 0; !glfwWindowShouldClose(window); ++frame) {
      if (options.beforeFrame) options.beforeFrame(frame);
      glfwPollEvents();
      int width = 0, height = 0;
      glfwGetFramebufferSize(window, &width, &height);
      width = std::max(width, window::kPanelWidth + 16), height = std::max(height, 16);
      std::string screenshot;
      bool quit = false;
      if (script) script->step(viewer, screenshot, quit);
      viewer.update();
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      viewer.handleMouse(window, width, height);
      viewer.handleKeys(window);
      bool shoot = false;
      viewer.drawPanel(width, height, shoot, quit);
      const bool pDown = glfwGetKey(window, GLFW_KEY_P) == GLFW_PRESS;
      shoot |= !ImGui::GetIO().WantCaptureKeyboard && pDown && !pWasDown;
      pWasDown = pDown;
      viewer.drawView(width, height);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glViewport(0, 0, width, height);
      ImGui::Render();
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      const bool lastFrame = options.frames > 0 && frame + 1 >= options.frames;
      if (shoot) writePng("isoatlas_view_" + std::to_string(shots++) + ".png", gl::readWindowImage(width, height));
      if (!screenshot.empty()) writePng(screenshot, gl::readWindowImage(width, height));
      if (lastFrame && !options.screenshot.empty()) writePng(options.screenshot, gl::readWindowImage(width, height));
      glfwSwapBuffers(window);
      const auto now = std::chrono::steady_clock::now();
      const double ms = std::chrono::duration<double, std::milli>(now - last).count();
      last = now;
      ModeFrames& f = report.modes[window::modeName(viewer.mode())];
      f.meanMs = (f.meanMs * f.frames + ms) / (f.frames + 1);
      f.maxMs = std::max(f.maxMs, ms);
      ++f.frames;
      if (lastFrame || quit) break;
    }
    report.iterations = viewer.iterations();
    report.backend = viewer.backendName();
    report.status = viewer.status();
    report.treeDabMs = viewer.treeDabLatencies();
    if (const auto point = viewer.slicePoint()) report.slicePoint = *point;
  }
  return report;
}

}  // namespace isoatlas::viewer

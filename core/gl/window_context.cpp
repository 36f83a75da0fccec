// Context::window: a GL context in a GLFW window. Apart from context.cpp so that GLFW is linked only
// by what opens a window (the view window, its tests).
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/error.h"
#include "core/gl/context.h"

namespace isoatlas::gl {

std::unique_ptr<Context> Context::window(int width, int height, const std::string& title, bool visible) {
  if (!glfwInit())
    throw Error("cannot open a window: GLFW found no display (set DISPLAY, or run under xvfb-run)", ErrorKind::Failure);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
#ifndef NDEBUG
  glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, GLFW_TRUE);
#endif
  GLFWwindow* window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window) {
    glfwTerminate();
    throw Error("cannot open an OpenGL 4.5 core window (the display's GL is too old?)", ErrorKind::Failure);
  }
  glfwMakeContextCurrent(window);
  static const WindowSystem glfw{glfwMakeContextCurrent, glfwGetCurrentContext, glfwDestroyWindow};
  std::unique_ptr<Context> ctx(new Context);
  ctx->window_ = window;
  ctx->windowSystem_ = &glfw;
  ctx->finishSetup("GLFW window");
  return ctx;
}

}  // namespace isoatlas::gl

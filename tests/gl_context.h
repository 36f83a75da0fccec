// The GL context of a test process: made on first use (headless: a GPU through EGL, else llvmpipe)
// and current from then on, as the isoatlas command makes one for its whole run.
#pragma once
#include <memory>

#include "core/gl/context.h"

namespace isoatlas::test {

inline gl::Context& glContext() {
  static const std::unique_ptr<gl::Context> context = gl::Context::headless();
  if (!context->isCurrent()) context->makeCurrent();
  return *context;
}

}  // namespace isoatlas::test

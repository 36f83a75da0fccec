#include "tests/viewer/fake_input.h"

#include <X11/Xlib.h>
#include <X11/extensions/XTest.h>
#include <X11/keysym.h>

namespace isoatlas::test {
namespace {

Display* x(void* display) { return static_cast<Display*>(display); }

}  // namespace

FakeInput::FakeInput() : display_(XOpenDisplay(nullptr)) {}

FakeInput::~FakeInput() {
  if (display_) XCloseDisplay(x(display_));
}

bool FakeInput::hasXTest() const {
  int event = 0, error = 0, major = 0, minor = 0;
  return XTestQueryExtension(x(display_), &event, &error, &major, &minor);
}

void FakeInput::moveTo(int px, int py) {
  XTestFakeMotionEvent(x(display_), -1, px, py, CurrentTime);
  XSync(x(display_), False);
}

void FakeInput::button(unsigned b, bool down) {
  XTestFakeButtonEvent(x(display_), b, down, CurrentTime);
  XSync(x(display_), False);
}

void FakeInput::key(Key k, bool down) {
  const KeySym sym = k == Key::Control ? XK_Control_L : k == Key::Z ? XK_z : XK_y;
  XTestFakeKeyEvent(x(display_), XKeysymToKeycode(x(display_), sym), down, CurrentTime);
  XSync(x(display_), False);
}

}  // namespace isoatlas::test

// FakeInput: mouse and key events sent to the X display a window runs on (Xvfb in the tests) through
// XTest, as a user's hand sends them: they reach the window through GLFW and Dear ImGui. Xlib's
// headers stay in fake_input.cpp (their macros clash with OpenMesh's and others').
#pragma once

namespace isoatlas::test {

class FakeInput {
public:
  enum class Key { Control, Z, Y };
  FakeInput();  // opens $DISPLAY
  ~FakeInput();
  FakeInput(const FakeInput&) = delete;
  FakeInput& operator=(const FakeInput&) = delete;
  bool open() const { return display_ != nullptr; }
  bool hasXTest() const;
  // Each call waits until the display has taken the event, so the window's next poll sees it.
  // Positions are on the screen (a window lies at its origin when there is no window manager).
  void moveTo(int x, int y);
  void button(unsigned button, bool down);  // 1 left, 3 right, 4 and 5 the wheel up and down
  void key(Key key, bool down);

private:
  void* display_;  // Display*
};

}  // namespace isoatlas::test

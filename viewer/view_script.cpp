#include "viewer/view_script.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/numbers.h"
#include "edit/solids/solid.h"
#include "viewer/viewer_state.h"

namespace isoatlas::viewer {
namespace {

const char* kUsage =
    "open FILE, mode segment|mesh|tree, tool navigate|probe|seed|unseed|brush, slice X,Y,Z, probe X,Y,Z[,R], seed X,Y,Z,R, unseed X,Y,Z,R, set t|eps|alpha V, run N, "
    "undo, redo, brush union|subtract SHAPE, stroke union|subtract R X,Y,Z..., paint union|subtract R i|j|k X,Y,Z..., view3d volume|surface, clip +x|-x|+y|-y|+z|-z|off, build, levels CPU GPU, stamp X,Y,Z,R,DEPTH WORD, wireframe on|off, render raycast|cubes, load-mask FILE, save-mask FILE, "
    "save-model FILE, save-tree FILE, screenshot FILE.png, frames N, quit";

// One line's action, its words checked.
ViewAction parseAction(const std::vector<std::string>& words, const std::string& where) {
  ViewAction a;
  a.verb = words[0];
  const auto args = words.size() - 1;
  auto need = [&](std::size_t n, const char* form) {
    if (args != n) throw Error(where + ": " + a.verb + " takes " + form);
  };
  auto oneOf = [&](const std::string& w, std::initializer_list<const char*> choices) {
    for (const char* c : choices)
      if (w == c) return;
    throw Error(where + ": " + a.verb + " " + w + ": not one of the choices (" + kUsage + ")");
  };
  auto count = [&](const std::string& w, const char* what) {
    const auto n = parseNumbers(w, where + ": " + a.verb, what);
    // Whole and at most a million (compared before any cast: a huge value must not reach one).
    if (n.size() != 1 || !(n[0] >= 0 && n[0] <= 1e6) || n[0] != std::floor(n[0]))
      throw Error(where + ": " + a.verb + " " + w + ": expected " + what + " (at most 1000000)");
    return n[0];
  };
  const std::string& v = a.verb;
  if (v == "open" || v == "load-mask" || v == "save-mask" || v == "save-model" || v == "save-tree" || v == "screenshot") {
    need(1, "a file");
    a.word = words[1];
    if (v == "screenshot" && !a.word.ends_with(".png")) throw Error(where + ": screenshot " + a.word + ": writes a .png");
    if (v == "save-model" && !a.word.ends_with(".isoatlas")) throw Error(where + ": save-model " + a.word + ": writes a .isoatlas");
    if (v == "save-tree" && !a.word.ends_with(".dvt")) throw Error(where + ": save-tree " + a.word + ": writes a .dvt");
  } else if (v == "tool") {
    need(1, "navigate, probe, seed, unseed or brush");
    if (!window::toolNamed(a.word = words[1])) throw Error(where + ": tool " + a.word + ": navigate, probe, seed, unseed or brush");
  } else if (v == "topology") {
    need(1, "free or preserve");
    oneOf(a.word = words[1], {"free", "preserve"});
  } else if (v == "mode") {
    need(1, "segment, mesh or tree");
    oneOf(a.word = words[1], {"segment", "mesh", "tree"});
  } else if (v == "slice") {
    need(1, "X,Y,Z");
    const Vec3 p = parsePoint(words[1], where + ": slice");
    a.numbers = {p.x, p.y, p.z};
  } else if (v == "probe" || v == "seed" || v == "unseed") {
    need(1, v == "probe" ? "X,Y,Z[,R]" : "X,Y,Z,R");
    a.numbers = parseNumbers(words[1], where + ": " + v, v == "probe" ? "X,Y,Z[,R]" : "X,Y,Z,R");
    if (v == "probe" && a.numbers.size() == 3) a.numbers.push_back(3);
    if (a.numbers.size() != 4 || a.numbers[3] <= 0)
      throw Error(where + ": " + v + " " + words[1] + ": expected X,Y,Z,R with R > 0 (mm)");
  } else if (v == "set") {
    need(2, "t, eps or alpha and a value");
    oneOf(a.word = words[1], {"t", "eps", "alpha"});
    a.numbers = parseNumbers(words[2], where + ": set " + a.word, "a number");
    if (a.numbers.size() != 1) throw Error(where + ": set " + a.word + " takes one number");
  } else if (v == "run" || v == "frames") {
    need(1, "a count");
    a.numbers = {count(words[1], "a count >= 0")};
  } else if (v == "levels") {
    need(2, "a CPU level and GPU halvings");
    a.numbers = {count(words[1], "a CPU level >= 0"), count(words[2], "GPU halvings >= 0")};
  } else if (v == "brush") {
    need(2, "union or subtract and a shape");
    oneOf(words[1], {"union", "subtract"});
    a.on = words[1] == "union";
    a.word = words[2];
    try {
      edit::dvt::parseBrush(a.word);
    } catch (const Error& e) {
      throw Error(where + ": brush " + e.what());
    }
  } else if (v == "stroke" || v == "paint") {
    const std::size_t first = v == "paint" ? 4 : 3;  // paint names the slice's voxel axis before its points
    if (words.size() <= first)
      throw Error(where + ": " + v + " takes union or subtract, a radius R (mm), " + (v == "paint" ? "i, j or k, " : "") +
                  "and the points X,Y,Z it passes through");
    oneOf(words[1], {"union", "subtract"});
    a.on = words[1] == "union";
    a.numbers = parseNumbers(words[2], where + ": " + v, "a radius R (mm)");
    if (a.numbers.size() != 1 || !(a.numbers[0] > 0)) throw Error(where + ": " + v + " " + words[2] + ": expected a radius R > 0 (mm)");
    if (v == "paint") oneOf(a.word = words[3], {"i", "j", "k"});
    for (std::size_t i = first; i < words.size(); ++i) {
      const Vec3 p = parsePoint(words[i], where + ": " + v);
      a.numbers.insert(a.numbers.end(), {p.x, p.y, p.z});
    }
  } else if (v == "wireframe") {
    need(1, "on or off");
    oneOf(words[1], {"on", "off"});
    a.on = words[1] == "on";
  } else if (v == "render") {
    need(1, "raycast or cubes");
    oneOf(a.word = words[1], {"raycast", "cubes"});
  } else if (v == "stamp") {
    need(2, "X,Y,Z,R,DEPTH and a word");
    a.numbers = parseNumbers(words[1], where + ": stamp", "X,Y,Z,R,DEPTH");
    if (a.numbers.size() != 5 || a.numbers[3] <= 0 || a.numbers[4] == 0)
      throw Error(where + ": stamp " + words[1] + ": expected X,Y,Z,R,DEPTH with R > 0 and DEPTH not 0 (mm)");
    a.word = words[2];
  } else if (v == "view3d") {
    need(1, "volume or surface");
    oneOf(a.word = words[1], {"volume", "surface"});
  } else if (v == "clip") {
    need(1, "+x, -x, +y, -y, +z, -z or off");
    oneOf(a.word = words[1], {"+x", "-x", "+y", "-y", "+z", "-z", "off"});
  } else if (v == "undo" || v == "redo" || v == "build" || v == "fill-threads" || v == "quit") {
    need(0, "nothing");
  } else {
    throw Error(where + ": " + v + " is not an action (" + kUsage + ")");
  }
  return a;
}

}  // namespace

std::string ViewAction::where() const { return script + ":" + std::to_string(line); }

std::vector<ViewAction> readViewScript(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot read the script");
  std::vector<ViewAction> actions;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    if (const auto hash = text.find('#'); hash != std::string::npos) text.resize(hash);
    std::istringstream words(text);
    std::vector<std::string> w;
    for (std::string word; words >> word;) w.push_back(word);
    if (w.empty()) continue;
    ViewAction a = parseAction(w, path + ":" + std::to_string(line));
    a.line = line, a.script = path;
    actions.push_back(std::move(a));
  }
  return actions;
}

namespace {

// A stroke action's points: its numbers after the radius, three a point.
std::vector<Vec3> strokePoints(const std::vector<double>& numbers) {
  std::vector<Vec3> points;
  for (std::size_t i = 1; i + 2 < numbers.size(); i += 3) points.push_back({numbers[i], numbers[i + 1], numbers[i + 2]});
  return points;
}

}  // namespace

void ScriptPlayer::step(window::Viewer& viewer, std::string& screenshot, bool& quit) {
  if (const std::string error = viewer.takeDeferredError(); !error.empty())
    throw Error((next_ > 0 ? actions_[next_ - 1].where() + ": " : std::string()) + error);
  if (framesLeft_ > 0) {
    --framesLeft_;
    return;
  }
  if (finished() || viewer.busy()) return;
  const ViewAction& a = actions_[next_++];
  try {
    perform(a, viewer, screenshot, quit);
  } catch (const std::exception& e) {
    throw Error(a.where() + ": " + e.what());
  }
}

void ScriptPlayer::perform(const ViewAction& a, window::Viewer& v, std::string& screenshot, bool& quit) {
  const auto& n = a.numbers;
  const std::string& verb = a.verb;
  if (verb == "open") v.show(window::load(a.word, v.readOptions()));
  else if (verb == "mode") v.setMode(a.word);
  else if (verb == "tool") v.setTool(a.word);
  else if (verb == "slice") v.slice({n[0], n[1], n[2]});
  else if (verb == "probe") v.probe({n[0], n[1], n[2]}, n[3]);
  else if (verb == "seed" || verb == "unseed") v.seed({n[0], n[1], n[2]}, n[3], verb == "seed");
  else if (verb == "set") v.set(a.word, n[0]);
  else if (verb == "topology") v.setTopology(a.word);
  else if (verb == "fill-threads") v.fillThreads();
  else if (verb == "run") v.run(int(n[0]));
  else if (verb == "undo") v.undo();
  else if (verb == "redo") v.redo();
  else if (verb == "brush") v.brush(a.word, a.on);
  else if (verb == "stroke") v.stroke(strokePoints(n), n[0], a.on);
  else if (verb == "paint") v.stroke(strokePoints(n), n[0], a.on, int(a.word[0] - 'i'));
  else if (verb == "build") v.build();
  else if (verb == "levels") v.levels(int(n[0]), int(n[1]));
  else if (verb == "view3d") v.view3d(a.word == "volume");
  else if (verb == "stamp") v.stamp({n[0], n[1], n[2]}, a.word, n[3], n[4]);
  else if (verb == "clip") v.clip(a.word);
  else if (verb == "wireframe") v.wireframe(a.on);
  else if (verb == "render") v.treeRender(a.word == "cubes");
  else if (verb == "load-mask") v.loadMask(a.word);
  else if (verb == "save-mask") v.saveMask(a.word);
  else if (verb == "save-model") v.saveModel(a.word);
  else if (verb == "save-tree") v.saveTree(a.word);
  else if (verb == "screenshot") screenshot = a.word;
  else if (verb == "frames") framesLeft_ = int(n[0]);
  else if (verb == "quit") quit = true;
}
std::vector<ViewAction> actions_;

}  // namespace isoatlas::viewer

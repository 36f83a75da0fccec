#include "edit/solids/solid.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.h"

namespace isoatlas::edit::dvt {
namespace {

class Sphere final : public DistanceSolid {
public:
  Sphere(Vec3 c, double r) : c_(c), r_(r) {}
  double signedDistance(const Vec3& p) const override { return norm(p - c_) - r_; }

private:
  Vec3 c_;
  double r_;
};

class Box final : public DistanceSolid {
public:
  Box(Vec3 lo, Vec3 hi) : centre_((lo + hi) * 0.5), half_((hi - lo) * 0.5) {}
  double signedDistance(const Vec3& p) const override {
    Vec3 q;
    for (int a = 0; a < 3; ++a) q[a] = std::abs(p[a] - centre_[a]) - half_[a];
    const Vec3 outside{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
    return norm(outside) + std::min(std::max({q.x, q.y, q.z}), 0.0);
  }

private:
  Vec3 centre_, half_;
};

class Capsule final : public DistanceSolid {
public:
  Capsule(Vec3 a, Vec3 b, double r) : a_(a), b_(b), r_(r) {}
  double signedDistance(const Vec3& p) const override {
    const Vec3 ab = b_ - a_, ap = p - a_;
    const double len2 = dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(dot(ap, ab) / len2, 0.0, 1.0) : 0.0;
    return norm(ap - ab * t) - r_;
  }

private:
  Vec3 a_, b_;
  double r_;
};

class Torus final : public DistanceSolid {
public:
  Torus(Vec3 c, double major, double minor) : c_(c), major_(major), minor_(minor) {}
  double signedDistance(const Vec3& p) const override {
    const Vec3 d = p - c_;
    const double ring = std::hypot(d.x, d.y) - major_;
    return std::hypot(ring, d.z) - minor_;
  }

private:
  Vec3 c_;
  double major_, minor_;
};

class Slab final : public DistanceSolid {
public:
  Slab(std::unique_ptr<DistanceSolid> shape, Vec3 point, Vec3 normal, double halfWidth)
      : shape_(std::move(shape)), point_(point), normal_(normal), halfWidth_(halfWidth) {}
  double signedDistance(const Vec3& p) const override {
    return std::max(shape_->signedDistance(p), std::abs(dot(p - point_, normal_)) - halfWidth_);
  }

private:
  std::unique_ptr<DistanceSolid> shape_;
  Vec3 point_, normal_;
  double halfWidth_;
};

bool finite(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

std::unique_ptr<DistanceSolid> sphereBrush(const Vec3& centre, double radius) {
  require(finite(centre) && std::isfinite(radius), "a sphere needs a finite centre and radius");
  require(radius > 0, "a sphere's radius must be > 0");
  return std::make_unique<Sphere>(centre, radius);
}

std::unique_ptr<DistanceSolid> capsuleBrush(const Vec3& a, const Vec3& b, double radius) {
  require(finite(a) && finite(b) && std::isfinite(radius), "a capsule needs finite ends and radius");
  require(radius > 0, "a capsule's radius must be > 0");
  return std::make_unique<Capsule>(a, b, radius);
}

std::unique_ptr<DistanceSolid> boxBrush(const Vec3& lo, const Vec3& hi) {
  require(finite(lo) && finite(hi), "a box needs finite corners");
  require(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z, "a box's extent must be > 0 on every axis");
  return std::make_unique<Box>(lo, hi);
}

std::unique_ptr<DistanceSolid> withinSlab(std::unique_ptr<DistanceSolid> shape, const Vec3& point, const Vec3& normal, double halfWidth) {
  require(std::abs(norm(normal) - 1) < 1e-9 && halfWidth > 0, "a slab needs a unit normal and a width > 0");
  return std::make_unique<Slab>(std::move(shape), point, normal, halfWidth);
}

float boundValue(double insideness, double radius) {
  const double v = std::clamp(insideness / radius, -1.0, 1.0);
  return v > 0 ? std::max(float(v), kNearZero) : std::min(float(v), -kNearZero);
}

CellClass DistanceSolid::classifyAt(const Vec3& centre, double radius, float* value) const {
  const double d = signedDistance(centre);
  if (d < -radius) return CellClass::Inside;
  if (d >= radius) return CellClass::Outside;
  if (value) *value = boundValue(-d, radius);
  return CellClass::Crossed;
}

CellClass DistanceSolid::classify(const TreeFrame& frame, const Cell& cell, double radius) const {
  return classifyAt(frame.centreWorld(cell), radius, nullptr);
}

float DistanceSolid::value(const TreeFrame& frame, const Cell& cell, double radius) const {
  return boundValue(-signedDistance(frame.centreWorld(cell)), radius);
}

CellClass DistanceSolid::classifyWithValue(const TreeFrame& frame, const Cell& cell, double radius, float& value) const {
  return classifyAt(frame.centreWorld(cell), radius, &value);
}

std::unique_ptr<DistanceSolid> parseBrush(const std::string& text) {
  const auto colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  const std::string usage = "\"" + text + "\": a shape is sphere:X,Y,Z,R  box:X0,Y0,Z0,X1,Y1,Z1  capsule:X0,Y0,Z0,X1,Y1,Z1,R  torus:X,Y,Z,R,r  or mesh:FILE";
  require(colon != std::string::npos, usage);
  std::vector<double> v;
  std::size_t at = colon + 1;
  while (at <= text.size()) {
    const std::size_t end = std::min(text.find(',', at), text.size());
    const std::string field = text.substr(at, end - at);
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(field, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    require(!field.empty() && used == field.size() && std::isfinite(x), "\"" + text + "\": \"" + field + "\" is not a finite number");
    v.push_back(x);
    at = end + 1;
  }
  auto need = [&](std::size_t n) {
    require(v.size() == n, "\"" + text + "\": " + kind + " takes " + std::to_string(n) + " numbers, not " + std::to_string(v.size()));
  };
  auto positive = [&](double x, const char* what) { require(x > 0, "\"" + text + "\": the " + std::string(what) + " must be > 0"); };
  if (kind == "sphere") {
    need(4), positive(v[3], "radius");
    return sphereBrush(Vec3{v[0], v[1], v[2]}, v[3]);
  }
  if (kind == "box") {
    need(6);
    for (int a = 0; a < 3; ++a) positive(v[3 + a] - v[a], "box's extent (X1 - X0, Y1 - Y0, Z1 - Z0)");
    return boxBrush(Vec3{v[0], v[1], v[2]}, Vec3{v[3], v[4], v[5]});
  }
  if (kind == "capsule") {
    need(7), positive(v[6], "radius");
    return capsuleBrush(Vec3{v[0], v[1], v[2]}, Vec3{v[3], v[4], v[5]}, v[6]);
  }
  if (kind == "torus") {
    need(5), positive(v[3], "major radius"), positive(v[4], "minor radius");
    return std::make_unique<Torus>(Vec3{v[0], v[1], v[2]}, v[3], v[4]);
  }
  throw Error(usage);
}

}  // namespace isoatlas::edit::dvt

#include "core/distance/triangle_tree.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/distance/morton_order.h"
#include "core/error.h"

namespace isoatlas {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;

Point point(const Vec3& p) { return {p.x, p.y, p.z}; }
Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Boxes are held in floats, rounded outwards so that a box holds every double coordinate of its
// triangles: half the bytes of doubles, so more of the tree stays in the cache.
float roundedDown(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -kInfinity) : f;
}
float roundedUp(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, kInfinity) : f;
}

struct NodeBox {
  std::array<float, 3> lo{kInfinity, kInfinity, kInfinity}, hi{-kInfinity, -kInfinity, -kInfinity};
  void add(const NodeBox& b) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], b.lo[k]), hi[k] = std::max(hi[k], b.hi[k]);
  }
};

// The squared distance from q to the box of triangle t: a bound below the triangle's own, cheaper than
// projecting onto it.
double triangleBoxSquaredDistance(const Kernel::Triangle_3& t, const Point& q) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double a = t.vertex(0)[k], b = t.vertex(1)[k], c = t.vertex(2)[k];
    const double below = std::min({a, b, c}) - q[k], above = q[k] - std::max({a, b, c});
    const double d = below > 0 ? below : above > 0 ? above : 0;
    d2 += d * d;
  }
  return d2;
}

// A triangle as the tree holds it, by value: a leaf's triangles are then read from one place, not
// from three points each anywhere in the mesh's.
struct HeldTriangle {
  Kernel::Triangle_3 triangle;
  std::uint32_t face;
};

// An allocator whose resize leaves new elements default-initialised (for these, not written): the
// tree's triangles are then written once, on every core, not zeroed first on one (a level of 8 M
// triangles holds 680 MB, and zeroing it cost more than filling it).
template <class T>
struct UnzeroedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UnzeroedAllocator<U>;
  };
  UnzeroedAllocator() = default;
  template <class U>
  UnzeroedAllocator(const UnzeroedAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// The tree: each node has up to four children, their boxes side by side (one coordinate of all four
// in a row, so the four distances are computed together). A child is a node, or a leaf of up to
// kLeafSize consecutive triangles, or nothing (an empty box, infinitely far).
constexpr std::uint32_t kLeafSize = 4;
constexpr std::uint32_t kNoSlot = ~std::uint32_t(0);
struct Node {
  std::array<std::array<float, 4>, 3> lo, hi;  // [axis][child]
  std::array<std::uint32_t, 4> index;          // a node, or a leaf's first triangle
  std::array<std::uint8_t, 4> count;           // a leaf's triangles; 0 for a node or nothing

  static Node nothing() {
    Node node;
    for (int c = 0; c < 4; ++c) node.set(c, NodeBox{}), node.index[c] = 0, node.count[c] = 0;
    return node;
  }
  void set(int child, const NodeBox& box) {
    for (int k = 0; k < 3; ++k) lo[k][child] = box.lo[k], hi[k][child] = box.hi[k];
  }
  // The four squared distances from q (given rounded outwards, qLo <= q <= qHi) to the boxes, each a
  // bound below the true one: rounding errors of the float arithmetic are taken off at the end. One
  // SSE lane a child.
  std::array<float, 4> squaredDistances(const std::array<float, 3>& qLo, const std::array<float, 3>& qHi) const {
    __m128 d2 = _mm_setzero_ps();
    for (int k = 0; k < 3; ++k) {
      const __m128 below = _mm_sub_ps(_mm_loadu_ps(lo[k].data()), _mm_set1_ps(qHi[k]));
      const __m128 above = _mm_sub_ps(_mm_set1_ps(qLo[k]), _mm_loadu_ps(hi[k].data()));
      const __m128 d = _mm_max_ps(_mm_max_ps(below, above), _mm_setzero_ps());
      d2 = _mm_add_ps(d2, _mm_mul_ps(d, d));
    }
    // Finite even where the squares overflow, so that a search with no bound yet still opens it.
    d2 = _mm_min_ps(_mm_mul_ps(d2, _mm_set1_ps(0.9999f)), _mm_set1_ps(std::numeric_limits<float>::max()));
    std::array<float, 4> out;
    _mm_storeu_ps(out.data(), d2);
    return out;
  }
};

// A range of triangles [begin, end) in Morton order.
struct Range {
  std::uint32_t begin, end;
  std::uint32_t size() const { return end - begin; }
};

// Where a range splits: where its Morton codes' highest differing bit turns on (the middle, when every
// code is the same).
std::uint32_t mortonSplit(const std::vector<std::uint64_t>& keys, Range r) {
  const std::uint32_t differ = mortonCode(keys[r.begin]) ^ mortonCode(keys[r.end - 1]);
  if (differ == 0) return r.begin + r.size() / 2;
  const std::uint32_t bit = std::uint32_t(1) << (31 - std::countl_zero(differ));
  return std::uint32_t(std::partition_point(keys.begin() + r.begin, keys.begin() + r.end,
                                            [&](std::uint64_t k) { return (mortonCode(k) & bit) == 0; }) -
                       keys.begin());
}

// The ranges a node's children stand for: two rounds of splits, a range of a leaf's size not split
// again (one range, a leaf, for a node over that few).
std::vector<Range> childRanges(const std::vector<std::uint64_t>& keys, Range r) {
  if (r.size() <= kLeafSize) return {r};
  std::vector<Range> out;
  const std::uint32_t middle = mortonSplit(keys, r);
  for (const Range half : {Range{r.begin, middle}, Range{middle, r.end}}) {
    if (half.size() <= kLeafSize) {
      out.push_back(half);
      continue;
    }
    const std::uint32_t quarter = mortonSplit(keys, half);
    out.push_back({half.begin, quarter});
    out.push_back({quarter, half.end});
  }
  return out;
}

}  // namespace

// A bounding volume hierarchy over the triangles, built in the Morton order of their centroids (one
// sort, then each range split where its keys first differ: no comparisons of boxes at every depth),
// the triangles held in leaf order. Closest points are CGAL's own projections onto the triangles, so a
// distance is the one CGAL's AABB tree gives.
struct TriangleTree::State {
  std::vector<HeldTriangle, UnzeroedAllocator<HeldTriangle>> triangles;
  std::vector<Node> nodes;
  std::vector<std::uint32_t> slotOfFace;  // where each face's triangle is held (faces left out: none)

  const Kernel::Triangle_3& triangle(std::uint32_t t) const { return triangles[t].triangle; }
  void build(const Mesh& mesh);
  NodeBox leafBox(Range range) const;
  NodeBox buildSubtree(std::vector<Node>& out, const std::vector<std::uint64_t>& keys, Range range, int sideBySideDepth) const;
  // Improves (best, bestFace, best2) with any triangle strictly nearer to q.
  void search(const Point& q, Point& best, std::uint32_t& bestFace, double& best2) const;
};

void TriangleTree::State::build(const Mesh& mesh) {
  std::vector<std::uint32_t> faces;
  faces.reserve(mesh.faceCount());
  for (std::size_t f = 0; f < mesh.faceCount(); ++f)
    if (namesThreeVertices(mesh.face(f))) faces.push_back(std::uint32_t(f));
  require(!faces.empty(), "a closest-point tree needs a triangle that names three vertices");
  const std::vector<std::uint64_t> keys = mortonOrder(faces.size(), [&](std::size_t i) {
    const auto c = mesh.face(faces[i]);
    return (mesh.positions[c[0]] + mesh.positions[c[1]] + mesh.positions[c[2]]) * (1.0 / 3);
  });
  triangles.resize(keys.size());
  slotOfFace.assign(mesh.faceCount(), kNoSlot);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, keys.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const std::uint32_t face = faces[mortonIndex(keys[i])];
      const auto c = mesh.face(face);
      const auto at = [&](int k) { return point(mesh.positions[c[k]]); };
      triangles[i] = {Kernel::Triangle_3(at(0), at(1), at(2)), face};
      slotOfFace[face] = std::uint32_t(i);
    }
  });
  nodes.reserve(triangles.size() / 3 + 1);
  buildSubtree(nodes, keys, {0, std::uint32_t(triangles.size())}, 2);
}

// The box of a leaf's triangles, bounded in doubles and rounded outwards once.
NodeBox TriangleTree::State::leafBox(Range range) const {
  std::array<double, 3> lo{triangles[range.begin].triangle.vertex(0).x(), triangles[range.begin].triangle.vertex(0).y(),
                           triangles[range.begin].triangle.vertex(0).z()},
      hi = lo;
  for (std::uint32_t t = range.begin; t < range.end; ++t)
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) {
        const double x = triangles[t].triangle.vertex(v)[k];
        lo[k] = std::min(lo[k], x), hi[k] = std::max(hi[k], x);
      }
  NodeBox box;
  for (int k = 0; k < 3; ++k) box.lo[k] = roundedDown(lo[k]), box.hi[k] = roundedUp(hi[k]);
  return box;
}

// The node over `range` and every node below it, appended to `out` (the node first, its subtrees
// after it); returns its box. The top `sideBySideDepth` levels build their large subtrees side by
// side, each into a list of its own, appended afterwards with its node numbers moved along (a few
// levels only: each level of them copies the nodes below it once more).
NodeBox TriangleTree::State::buildSubtree(std::vector<Node>& out, const std::vector<std::uint64_t>& keys, Range range,
                                          int sideBySideDepth) const {
  const std::size_t index = out.size();
  out.push_back(Node::nothing());
  const std::vector<Range> children = childRanges(keys, range);
  const bool sideBySide = sideBySideDepth > 0 && range.size() > (1u << 15);
  std::array<NodeBox, 4> boxes;
  std::array<std::vector<Node>, 4> parts;
  const auto subtree = [&](std::size_t c, std::vector<Node>& into) { return buildSubtree(into, keys, children[c], sideBySideDepth - 1); };
  if (sideBySide)
    tbb::parallel_for(std::size_t(0), children.size(), [&](std::size_t c) {
      if (children[c].size() <= kLeafSize) return;
      parts[c].reserve(children[c].size() / 3 + 1);  // as build() reserves: no copies as the part grows
      boxes[c] = subtree(c, parts[c]);
    });
  for (std::size_t c = 0; c < children.size(); ++c) {
    if (children[c].size() <= kLeafSize) {
      boxes[c] = leafBox(children[c]);
      out[index].index[c] = children[c].begin, out[index].count[c] = std::uint8_t(children[c].size());
    } else if (!sideBySide) {
      const std::size_t child = out.size();
      boxes[c] = subtree(c, out);
      out[index].index[c] = std::uint32_t(child);
    } else {
      // A part's own first node is its root; no child names it, so a node number 0 is still nothing.
      const std::uint32_t offset = std::uint32_t(out.size());
      for (Node node : parts[c]) {
        for (int k = 0; k < 4; ++k)
          if (node.count[k] == 0 && node.index[k] != 0) node.index[k] += offset;
        out.push_back(node);
      }
      out[index].index[c] = offset;
    }
    out[index].set(int(c), boxes[c]);
  }
  NodeBox box;
  for (std::size_t c = 0; c < children.size(); ++c) box.add(boxes[c]);
  return box;
}

// Depth first, the nearer children first, a child skipped once its box is no nearer than the best so
// far (CGAL's AABB tree goes left to right; the order only speeds the search).
void TriangleTree::State::search(const Point& q, Point& best, std::uint32_t& bestFace, double& best2) const {
  const auto project = Kernel().construct_projected_point_3_object();
  const std::array<float, 3> qLo{roundedDown(q.x()), roundedDown(q.y()), roundedDown(q.z())},
      qHi{roundedUp(q.x()), roundedUp(q.y()), roundedUp(q.z())};
  struct Pending {
    std::uint32_t index, count;  // a node (count 0) or a leaf
    double d2;
  };
  // A node opened leaves at most three more on the stack than before. Each split either drops a bit of
  // the 30-bit codes or halves a run of equal codes, so a node's depth is below (30 + 32) / 2 + 1 and
  // the stack below 3 x 32 + 4 entries.
  std::array<Pending, 256> stack;
  std::size_t size = 0;
  stack[size++] = {0, 0, 0};
  while (size > 0) {
    const Pending top = stack[--size];
    if (!(top.d2 < best2)) continue;
    if (top.count > 0) {
      for (std::uint32_t t = top.index; t < top.index + top.count; ++t) {
        const Kernel::Triangle_3& triangle = this->triangle(t);
        if (!(triangleBoxSquaredDistance(triangle, q) < best2)) continue;
        const Point p = project(triangle, q);
        const double d2 = CGAL::squared_distance(q, p);
        if (d2 < best2) best = p, bestFace = triangles[t].face, best2 = d2;
      }
      continue;
    }
    const Node& node = nodes[top.index];
    const std::array<float, 4> d2 = node.squaredDistances(qLo, qHi);
    // The children near enough pushed farthest first, so that the nearest is searched first.
    const std::size_t first = size;
    for (int c = 0; c < 4; ++c) {
      if (!(double(d2[c]) < best2) || (node.count[c] == 0 && node.index[c] == 0)) continue;
      std::size_t k = size++;
      for (; k > first && stack[k - 1].d2 < d2[c]; --k) stack[k] = stack[k - 1];
      stack[k] = {node.index[c], node.count[c], d2[c]};
    }
  }
}

TriangleTree::TriangleTree(const Mesh& mesh) : state_(std::make_unique<State>()) {
  require(mesh.allFacesHave(3), "a closest-point tree needs a triangle mesh");
  state_->build(mesh);
}

TriangleTree::~TriangleTree() = default;
TriangleTree::TriangleTree(TriangleTree&&) noexcept = default;

TriangleTree::Closest TriangleTree::closest(const Vec3& q) const {
  Point best;
  std::uint32_t face = 0;
  double best2 = std::numeric_limits<double>::infinity();
  state_->search(point(q), best, face, best2);
  return {vec(best), face};
}

// The hint's point bounds the search, and so does its face's own closest point (usually the answer,
// or next to it, when the last query was near): the tighter the bound, the fewer boxes opened.
TriangleTree::Closest TriangleTree::closest(const Vec3& q, const Closest& hint) const {
  const Point p = point(q);
  Point best = point(hint.point);
  std::uint32_t face = hint.face;
  double best2 = CGAL::squared_distance(p, best);
  if (hint.face < state_->slotOfFace.size() && state_->slotOfFace[hint.face] != kNoSlot) {
    const Point onFace = Kernel().construct_projected_point_3_object()(state_->triangle(state_->slotOfFace[hint.face]), p);
    if (const double d2 = CGAL::squared_distance(p, onFace); d2 < best2) best = onFace, best2 = d2;
  }
  state_->search(p, best, face, best2);
  return {vec(best), face};
}

Vec3 TriangleTree::closestPoint(const Vec3& q, const Vec3& hint) const {
  return closest(q, Closest{hint, std::numeric_limits<std::uint32_t>::max()}).point;
}

double TriangleTree::distance(const Vec3& q) const { return norm(q - closest(q).point); }

namespace {

// Whether the ray meets child c's box; the slabs widened by a rounding margin, so a ray grazing the
// box of a triangle it meets is never turned away (the triangle itself decides, by CGAL's test).
bool rayMeetsBox(const Point& origin, const std::array<double, 3>& inverse, const std::array<std::array<float, 4>, 3>& lo,
                 const std::array<std::array<float, 4>, 3>& hi, int c) {
  double enter = 0, leave = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (lo[k][c] > hi[k][c]) return false;  // nothing there
    const double margin = 1e-9 * (std::abs(double(lo[k][c])) + std::abs(double(hi[k][c])) + 1);
    const double lower = double(lo[k][c]) - margin - origin[k], upper = double(hi[k][c]) + margin - origin[k];
    if (std::isinf(inverse[k])) {  // parallel to this slab: inside it or never
      if (lower > 0 || upper < 0) return false;
      continue;
    }
    double t0 = lower * inverse[k], t1 = upper * inverse[k];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0), leave = std::min(leave, t1);
    if (enter > leave) return false;
  }
  return true;
}

}  // namespace

std::size_t TriangleTree::crossings(const Vec3& origin, const Vec3& direction) const {
  const Point o = point(origin);
  const Kernel::Ray_3 ray(o, Kernel::Vector_3(direction.x, direction.y, direction.z));
  const std::array<double, 3> inverse{1 / direction.x, 1 / direction.y, 1 / direction.z};
  std::size_t count = 0;
  std::vector<std::uint32_t> stack{0};
  while (!stack.empty()) {
    const Node& node = state_->nodes[stack.back()];
    stack.pop_back();
    for (int c = 0; c < 4; ++c) {
      if (!rayMeetsBox(o, inverse, node.lo, node.hi, c)) continue;
      if (node.count[c] == 0) {
        stack.push_back(node.index[c]);
        continue;
      }
      for (std::uint32_t t = node.index[c]; t < node.index[c] + node.count[c]; ++t)
        count += CGAL::do_intersect(ray, state_->triangle(t)) ? 1 : 0;
    }
  }
  return count;
}

}  // namespace isoatlas

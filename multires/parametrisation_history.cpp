#include "multires/parametrisation_history.h"

#include <algorithm>
#include <cstring>

#include "core/error.h"
#include "multires/exact_orientation.h"

namespace isoatlas::multires {

void ParametrisationHistory::beginStep(std::span<const Vec2> layout) {
  require(layout.size() <= 255, "parametrisation history: a ring of more than 255 vertices");
  const std::size_t at = (records_.size() + 7) / 8 * 8;
  require(at + sizeof(StepHeader) + layout.size() * sizeof(Vec2) + 255 * sizeof(ReplacedFace) < std::size_t(~0u),
          "parametrisation history: more than 4 GiB of steps");
  lastStep_ = std::uint32_t(at);
  ++steps_;
  const StepHeader header{std::uint16_t(layout.size()), 0, 0};
  records_.resize(at + sizeof header + layout.size() * sizeof(Vec2));
  std::memcpy(records_.data() + at, &header, sizeof header);
  std::memcpy(records_.data() + at + sizeof header, layout.data(), layout.size() * sizeof(Vec2));
}

void ParametrisationHistory::reserve(std::size_t steps) {
  constexpr std::size_t kRing = 8;  // layout points, and faces replaced; made faces two fewer
  records_.reserve(steps * (sizeof(StepHeader) + (kRing + 1) * sizeof(Vec2) + kRing * sizeof(ReplacedFace)));
  made_.reserve(steps * (kRing - 2));
}

std::size_t ParametrisationHistory::replacedOffset(std::uint32_t at) const {
  const auto* header = reinterpret_cast<const StepHeader*>(records_.data() + at);
  return at + sizeof(StepHeader) + header->layoutSize * sizeof(Vec2);
}

ParametrisationHistory::StepRecord ParametrisationHistory::record(std::uint32_t at) const {
  return {reinterpret_cast<const StepHeader*>(records_.data() + at), reinterpret_cast<const Vec2*>(records_.data() + at + sizeof(StepHeader)),
          reinterpret_cast<const ReplacedFace*>(records_.data() + replacedOffset(at))};
}

ParametrisationHistory::StepHeader& ParametrisationHistory::headerOf(std::uint32_t at) {
  return *reinterpret_cast<StepHeader*>(records_.data() + at);
}

ParametrisationHistory::ReplacedFace* ParametrisationHistory::replacedFaces(std::uint32_t at) {
  return reinterpret_cast<ReplacedFace*>(records_.data() + replacedOffset(at));
}

void ParametrisationHistory::replaces(std::uint32_t version, const std::array<std::uint8_t, 3>& corners) {
  const std::uint16_t here = headerOf(lastStep_).replacedSize;
  require(here < kNoFaceAcross, "parametrisation history: a step replaced more than 254 faces");
  ReplacedFace face;
  face.version = version;
  face.corners = corners;
  // Side i runs from corner i + 1 to corner i + 2; the face across has it the other way round.
  const auto from = [](const Face& f, int i) { return f.corners[std::size_t(i + 1) % 3]; };
  const auto to = [](const Face& f, int i) { return f.corners[std::size_t(i + 2) % 3]; };
  ReplacedFace* replaced = replacedFaces(lastStep_);
  for (std::uint8_t g = 0; g < here; ++g) {
    ReplacedFace& other = replaced[g];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (from(face, i) == to(other, j) && to(face, i) == from(other, j))
          face.across[std::size_t(i)] = g, other.across[std::size_t(j)] = std::uint8_t(here);
  }
  records_.resize(records_.size() + sizeof face);  // moves the bytes: `replaced` is not used past here
  std::memcpy(replacedFaces(lastStep_) + here, &face, sizeof face);
  ++headerOf(lastStep_).replacedSize;
}

std::uint32_t ParametrisationHistory::adds(const std::array<std::uint8_t, 3>& corners) {
  made_.push_back({lastStep_, corners});
  return denseFaces_ + std::uint32_t(made_.size() - 1);
}

namespace {

// A point on an edge (or at a corner) of the face a step made, where a face the step replaced has
// that edge too (the same two ring points): that face and the same weights on the same two corners,
// carried over exactly. The faces on both sides of an edge then lead to the same dense point bit for
// bit; placing the point in the layout and locating it again would round, and a thin face can turn
// that rounding into a jump of its own size. -1 when the point is inside the face, or no replaced
// face has its edge.
template <class Face>
int alongKeptEdge(const std::array<std::uint8_t, 3>& madeCorners, const std::array<double, 3>& bary, const Face* replaced,
                  std::size_t count, std::array<double, 3>& carried) {
  if (bary[0] != 0 && bary[1] != 0 && bary[2] != 0) return -1;
  for (std::size_t r = 0; r < count; ++r) {
    std::array<double, 3> w{0, 0, 0};
    bool holds = true;
    for (int k = 0; k < 3 && holds; ++k) {
      if (bary[k] == 0) continue;
      const auto* at = std::find(replaced[r].corners.begin(), replaced[r].corners.end(), madeCorners[k]);
      holds = at != replaced[r].corners.end();
      if (holds) w[std::size_t(at - replaced[r].corners.begin())] = bary[k];
    }
    if (holds) {
      carried = w;
      return int(r);
    }
  }
  return -1;
}

}  // namespace

ParametrisationHistory::DensePoint ParametrisationHistory::toDense(std::uint32_t version, const Bary& bary, Hints* hints) const {
  DensePoint out{version, bary, 0, 0};
  while (out.face >= denseFaces_) {
    const Face& made = made_[out.face - denseFaces_];
    const StepRecord step = record(made.version);
    const Vec2* layout = step.layout;
    const ReplacedFace* replaced = step.replaced;
    const std::size_t replacedSize = step.header->replacedSize;
    Bary carried;
    if (const int r = alongKeptEdge(made.corners, out.bary, replaced, replacedSize, carried); r >= 0) {
      out.face = replaced[r].version;
      out.bary = carried;
      ++out.steps;
      continue;
    }
    const Vec2 p = layout[made.corners[0]] * out.bary[0] + layout[made.corners[1]] * out.bary[1] +
                   layout[made.corners[2]] * out.bary[2];
    auto corners = [&](std::size_t i) {
      const auto& c = replaced[i].corners;
      return std::array<Vec2, 3>{layout[c[0]], layout[c[1]], layout[c[2]]};
    };
    const std::uint32_t stepIndex = made.version;  // where its record starts: the hints' name for the step
    TriangleHit hit;
    if (hints)
      if (const std::size_t face = hints->face(stepIndex); face < replacedSize)
        hit = walkStrictlyInside(p, face, replacedSize, corners,
                                 [&](std::size_t f, int i) {
                                   const std::uint8_t g = replaced[f].across[std::size_t(i)];
                                   return g == kNoFaceAcross ? kNoTriangleHit : std::size_t(g);
                                 });
    if (hit.triangle == kNoTriangleHit) hit = locateExactly(p, replacedSize, corners);
    if (hints && hit.triangle != kNoTriangleHit) hints->remember(stepIndex, hit.triangle);
    if (hit.triangle == kNoTriangleHit) {
      hit = locateInTriangles(p, replacedSize, corners);
      if (hit.triangle == kNoTriangleHit) throw Error("parametrisation history: a step replaced only flat faces", ErrorKind::Failure);
      const std::array<Vec2, 3> c = corners(hit.triangle);
      const Bary raw = barycentric2(p, c[0], c[1], c[2]);
      out.outside = std::max(out.outside, -std::min({raw[0], raw[1], raw[2]}));
    }
    out.face = replaced[hit.triangle].version;
    out.bary = hit.bary;
    ++out.steps;
  }
  return out;
}

std::size_t ParametrisationHistory::bytes() const {
  return records_.size() + made_.size() * sizeof(Face);
}

}  // namespace isoatlas::multires

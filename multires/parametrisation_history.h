// ParametrisationHistory: the parametrisation of a dense mesh over its base mesh kept exactly, as the
// record of the stellar simplification that made it (successive self-parametrisation, Liu et al.
// 2020). Each step removed one vertex and re-triangulated its ring: it is recorded as the ring laid
// flat (the removed vertex at the origin) with the faces it replaced and the faces it made, two
// triangulations of one polygon that planWeld checked by exact predicates. A point of a face is
// carried back to the dense mesh step by step: placed in the step's layout by its weights in the
// face that step made, found by exact point location among the faces it replaced, and so on down to
// a dense face. The map is therefore one-to-one and onto: no point is lost in a gap, none is claimed
// twice, whatever the dense triangles look like drawn straight across the base mesh. A point on an
// edge that a step kept (or at one of its corners) is carried to the replaced face with that edge at
// the same weights, never placed and located again: the faces on the two sides of an edge map it to
// the same dense point bit for bit, so the charts on either side of a base edge agree on their border.
//
// Faces are named by versions: dense face f is version f; each step's new faces get new versions.
// A version's weights refer to its corners in the order it was recorded with.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/huge_pages.h"
#include "core/mesh.h"
#include "multires/vec2.h"

namespace isoatlas::multires {

class ParametrisationHistory {
public:
  using Bary = std::array<double, 3>;
  explicit ParametrisationHistory(std::uint32_t denseFaces) : denseFaces_(denseFaces) {}

  // Recording a step: the ring's layout (its points, by local index), then each face it replaces
  // (a version, with its corners as local indices in that version's corner order), then each face
  // it makes (corners as local indices); adds returns the new version.
  void beginStep(std::span<const Vec2> layout);
  // Room for about `steps` steps (rings of up to 8 vertices), so that recording them seldom moves the
  // records: a move copies them and clears fresh huge pages. Pages are only touched when written.
  void reserve(std::size_t steps);
  void replaces(std::uint32_t version, const std::array<std::uint8_t, 3>& corners);
  std::uint32_t adds(const std::array<std::uint8_t, 3>& corners);

  // Where a point of face `version` at weights `bary` comes from on the dense mesh: a dense face and
  // weights of its corners (dense.face order). At a step where no replaced face holds the point by
  // exact test (its place in the step's layout is computed in floating point, so a point on the
  // ring's border may fall just outside), it goes to the nearest face, and `outside` keeps the
  // largest such miss as a weight (0: every step held the point exactly; rounding: ~1e-16).
  struct DensePoint {
    std::uint32_t face = 0;
    Bary bary{};
    double outside = 0;
    std::uint32_t steps = 0;  // the steps walked back
  };
  // A miss past this weight is a gap in the map, not rounding.
  static constexpr double kGapWeight = 1e-9;
  // Which face each step found a point in last (a small table by step): points near each other take
  // the same way back, so the walk to the face holding it starts there. Hints change how fast toDense
  // is, never what it gives: the walk ends only at a face holding the point strictly inside, where no
  // other can.
  class Hints {
  public:
    // step: where the step's record starts (toDense's name for it)
    std::size_t face(std::uint32_t step) const {
      const Entry& e = entries_[slot(step)];
      return e.step == step ? e.face : kNoTriangleHit;
    }
    void remember(std::uint32_t step, std::size_t face) { entries_[slot(step)] = {step, std::uint32_t(face)}; }

  private:
    static constexpr std::size_t kEntries = 4096;
    static std::size_t slot(std::uint32_t step) { return std::uint32_t(step * 0x9E3779B1u) >> 20; }  // 12 bits
    struct Entry {
      std::uint32_t step = ~0u, face = 0;
    };
    std::array<Entry, kEntries> entries_{};
  };
  DensePoint toDense(std::uint32_t version, const Bary& bary, Hints* hints = nullptr) const;

  std::uint32_t denseFaces() const { return denseFaces_; }
  std::uint32_t versions() const { return denseFaces_ + std::uint32_t(made_.size()); }
  std::size_t steps() const { return steps_; }
  std::size_t bytes() const;

private:
  // Each step's record lies in one run of bytes, its header, its ring's layout and then the faces it
  // replaced, so that a walk back reads one place per step besides the made face that leads there:
  // toDense spends most of its time waiting on memory.
  struct StepHeader {
    std::uint16_t layoutSize, replacedSize;
    std::uint32_t padding;  // to 8 bytes, so that the layout's doubles after it are aligned
  };
  struct Face {
    std::uint32_t version;  // the replaced face's; for a made face, where its step's record starts in records_
    std::array<std::uint8_t, 3> corners;
  };
  // A face a step replaced, with the step's face across each of its sides (side i faces corner i;
  // kNoFaceAcross on the ring's border), linked as the faces are recorded: a walk through the step's
  // faces crosses a side without searching for its neighbour.
  static constexpr std::uint8_t kNoFaceAcross = 0xff;
  struct ReplacedFace : Face {
    std::array<std::uint8_t, 3> across{kNoFaceAcross, kNoFaceAcross, kNoFaceAcross};
  };
  static_assert(sizeof(StepHeader) == 8 && sizeof(Vec2) == 16 && alignof(ReplacedFace) <= 8);
  struct StepRecord {
    const StepHeader* header;
    const Vec2* layout;
    const ReplacedFace* replaced;
  };
  StepRecord record(std::uint32_t at) const;
  std::size_t replacedOffset(std::uint32_t at) const;  // where step `at`'s replaced faces start in records_
  // The step being recorded, at `at`: its header, its replaced faces.
  StepHeader& headerOf(std::uint32_t at);
  ReplacedFace* replacedFaces(std::uint32_t at);
  std::uint32_t denseFaces_;
  std::size_t steps_ = 0;
  std::uint32_t lastStep_ = 0;   // where the step being recorded starts in records_
  // Walks back read both at scattered places, many times over: huge pages spare the TLB.
  HugePageVector<std::byte> records_;  // each step's record starting 8-byte aligned
  HugePageVector<Face> made_;  // per version past the dense faces: its step's record, its corners there
};

// The point of the dense surface a DensePoint names.
inline Vec3 densePosition(const Mesh& dense, const ParametrisationHistory::DensePoint& p) {
  const auto c = dense.face(p.face);
  return dense.positions[c[0]] * p.bary[0] + dense.positions[c[1]] * p.bary[1] + dense.positions[c[2]] * p.bary[2];
}

// A base triangle's place in the history: the face version it lies in, and its corners' weights
// there (a triangle split after simplification is part of one).
struct HistoryFrame {
  std::uint32_t version = 0;
  std::array<std::array<double, 3>, 3> corner{};  // corner i's weights in the version's face
  ParametrisationHistory::Bary toVersion(const ParametrisationHistory::Bary& bary) const {
    ParametrisationHistory::Bary w{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) w[j] += bary[i] * corner[i][j];
    return w;
  }
};

}  // namespace isoatlas::multires

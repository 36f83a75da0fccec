// Solids a DVT write takes (Keller et al., sec. 4.4): implicit brushes (sphere, box, capsule, torus),
// closed triangle meshes (mesh_solid.h) and segmentations (volume_solid.h). A cell's centre is inside
// a solid when the solid's inside-ness there is > 0.
#pragma once
#include <memory>
#include <string>

#include "core/vec.h"
#include "edit/dvt/volume_tree.h"

namespace isoatlas::edit::dvt {

enum class CellClass { Inside, Outside, Crossed };

class Solid {
public:
  virtual ~Solid() = default;
  // Inside: every point of the cell is inside; Outside: none is; Crossed: either may hold. `radius`:
  // frame.radius(cell.depth), which the caller keeps per depth.
  virtual CellClass classify(const TreeFrame& frame, const Cell& cell, double radius) const = 0;
  // The cell's leaf value (volume_tree.h): the inside-ness of its centre over R(depth), clamped to
  // [-1, 1], never 0 (boundValue).
  virtual float value(const TreeFrame& frame, const Cell& cell, double radius) const = 0;
  // classify, and for a crossed cell its value too (one evaluation where a solid can).
  virtual CellClass classifyWithValue(const TreeFrame& frame, const Cell& cell, double radius, float& value) const {
    const CellClass k = classify(frame, cell, radius);
    if (k == CellClass::Crossed) value = this->value(frame, cell, radius);
    return k;
  }
};

// A solid from a signed distance (negative inside, 1-Lipschitz, world units): a cell is inside when
// its centre is deeper inside than the cell's radius, outside when farther out.
class DistanceSolid : public Solid {
public:
  virtual double signedDistance(const Vec3& world) const = 0;
  CellClass classify(const TreeFrame& frame, const Cell& cell, double radius) const override;
  float value(const TreeFrame& frame, const Cell& cell, double radius) const override;
  CellClass classifyWithValue(const TreeFrame& frame, const Cell& cell, double radius, float& value) const override;
  // The same for a cell given by its centre in the world (the rasteriser keeps centres as it splits);
  // the value only where `value` is given.
  CellClass classifyAt(const Vec3& centre, double radius, float* value) const;
};

// Inside-ness over a radius as a leaf value: clamped to [-1, 1], at least kNearZero from 0 with the
// sign of `insideness` (0 counts as outside).
float boundValue(double insideness, double radius);

// `shape` cut to the slab of points within `halfWidth` of the plane through `point` normal to
// `normal` (a unit vector): the larger of the two signed distances, a bound as classify needs it.
// A brush painting one layer of voxels, as a 2D brush on a slice does.
std::unique_ptr<DistanceSolid> withinSlab(std::unique_ptr<DistanceSolid> shape, const Vec3& point, const Vec3& normal, double halfWidth);

// A sphere, a capsule (the sphere swept from a to b) and an axis-aligned box, in world coordinates;
// radius > 0, hi > lo on every axis.
std::unique_ptr<DistanceSolid> sphereBrush(const Vec3& centre, double radius);
std::unique_ptr<DistanceSolid> capsuleBrush(const Vec3& a, const Vec3& b, double radius);
std::unique_ptr<DistanceSolid> boxBrush(const Vec3& lo, const Vec3& hi);

// An implicit brush from its command-line form, in world coordinates: sphere:X,Y,Z,R
// box:X0,Y0,Z0,X1,Y1,Z1  capsule:X0,Y0,Z0,X1,Y1,Z1,R  torus:X,Y,Z,R,r (in the plane z = Z). Throws
// Error naming the text on a malformed one (unknown kind, wrong count, not finite, sizes <= 0).
std::unique_ptr<DistanceSolid> parseBrush(const std::string& text);

}  // namespace isoatlas::edit::dvt

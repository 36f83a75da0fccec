// VolumeSource: a scalar volume read a row at a time, as floats, so that what reads it (the level
// set's solvers, page by page as the band reaches them) holds only the parts it works on, not the
// volume. VolumeInMemory is a Volume held in memory; sources that read a file as they go are issue
// 67's next step.
//   geometry()  dims, spacing, origin, direction and scalar type; no voxels
//   readRow     voxels x0 .. x0 + n - 1 of row (y, z), as floats (the row must lie inside); called
//               from one thread at a time by each reader (a source shared by several readers must
//               take concurrent calls)
//   wholeBytes  whether every voxel is a whole number from 0 to 255 (a reader may then keep bytes)
//   heldBytes   the memory the source itself holds (a reader counts it in its own)
#pragma once
#include <cstdint>
#include <memory>

#include "core/volume.h"

namespace isoatlas {

class VolumeSource {
public:
  virtual ~VolumeSource() = default;
  const Volume& geometry() const { return geometry_; }
  virtual void readRow(std::int64_t x0, std::int64_t y, std::int64_t z, std::int64_t n, float* out) const = 0;
  virtual bool wholeBytes() const = 0;
  virtual std::uint64_t heldBytes() const = 0;

protected:
  explicit VolumeSource(const Volume& v);  // takes v's geometry, not its voxels

private:
  Volume geometry_;
};

class VolumeInMemory final : public VolumeSource {
public:
  // Holds the volume (move it in to spare a copy); throws Error for voxels that do not fill its dims.
  explicit VolumeInMemory(Volume volume);
  // The same values held as compactly as readRow gives them: as bytes where every voxel is a whole
  // number from 0 to 255, else as floats (a level set's copy of its source).
  static std::shared_ptr<const VolumeInMemory> compact(const Volume& volume);
  void readRow(std::int64_t x0, std::int64_t y, std::int64_t z, std::int64_t n, float* out) const override;
  bool wholeBytes() const override { return wholeBytes_; }
  std::uint64_t heldBytes() const override { return volume_.data.size(); }

private:
  Volume volume_;
  bool wholeBytes_ = false;
};

}  // namespace isoatlas

// NRRD (.nrrd, .nhdr with its data file) through teem. World coordinates become RAS, as 3D Slicer
// shows them: an LPS file's x and y are negated on reading and again on writing (we write LPS, the
// space ITK and Slicer write). A 4D file is a series of 3D volumes along its one non-spatial axis
// (a diffusion series' list axis, first; a Slicer sequence's, last), read one volume at a time.
#include <teem/nrrd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include "core/error.h"
#include "core/gz_file.h"
#include "core/volume_io.h"

namespace isoatlas {
namespace {

struct NrrdDeleter {
  void operator()(Nrrd* n) const { nrrdNuke(n); }
};
struct IoDeleter {
  void operator()(NrrdIoState* n) const { nrrdIoStateNix(n); }
};
using NrrdPtr = std::unique_ptr<Nrrd, NrrdDeleter>;

std::string teemError() {
  char* err = biffGetDone(NRRD);
  std::string msg = err ? err : "unknown teem error";
  std::free(err);
  while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
  // teem's messages are nested "[nrrd] fn: ..." lines; the last line is the root cause.
  const auto nl = msg.rfind('\n');
  if (nl != std::string::npos) msg = msg.substr(nl + 1);
  const auto bracket = msg.find("] ");
  if (bracket != std::string::npos) msg = msg.substr(bracket + 2);
  return msg;
}

bool scalarTypeFromNrrd(int t, ScalarType& out) {
  switch (t) {
    case nrrdTypeUChar: out = ScalarType::UInt8; return true;
    case nrrdTypeChar: out = ScalarType::Int8; return true;
    case nrrdTypeUShort: out = ScalarType::UInt16; return true;
    case nrrdTypeShort: out = ScalarType::Int16; return true;
    case nrrdTypeUInt: out = ScalarType::UInt32; return true;
    case nrrdTypeInt: out = ScalarType::Int32; return true;
    case nrrdTypeFloat: out = ScalarType::Float32; return true;
    case nrrdTypeDouble: out = ScalarType::Float64; return true;
    default: return false;
  }
}

int nrrdTypeOf(ScalarType t) {
  switch (t) {
    case ScalarType::UInt8: return nrrdTypeUChar;
    case ScalarType::Int8: return nrrdTypeChar;
    case ScalarType::UInt16: return nrrdTypeUShort;
    case ScalarType::Int16: return nrrdTypeShort;
    case ScalarType::UInt32: return nrrdTypeUInt;
    case ScalarType::Int32: return nrrdTypeInt;
    case ScalarType::Float32: return nrrdTypeFloat;
    case ScalarType::Float64: return nrrdTypeDouble;
  }
  return nrrdTypeFloat;
}

// Header only, or header and data, into a fresh Nrrd.
NrrdPtr load(const std::string& path, bool skipData) {
  NrrdPtr nrrd(nrrdNew());
  std::unique_ptr<NrrdIoState, IoDeleter> io(nrrdIoStateNew());
  nrrdIoStateSet(io.get(), nrrdIoStateSkipData, skipData ? AIR_TRUE : AIR_FALSE);
  if (nrrdLoad(nrrd.get(), path.c_str(), io.get())) throw Error(path + ": not a readable NRRD file: " + teemError());
  if (skipData) {
    // A detached header may name any file as its data: only regular files are read (a FIFO or a
    // device could block or never end).
    for (unsigned i = 0; io->dataFNArr && i < io->dataFNArr->len; ++i) {
      const char* name = io->dataFN[i];
      std::string full = name ? name : "";
      if (!full.empty() && full[0] != '/' && io->path) full = std::string(io->path) + "/" + full;
      std::error_code ec;
      if (!std::filesystem::is_regular_file(full, ec))
        throw Error(path + ": NRRD data file \"" + (name ? name : "") + "\" is not a regular file");
    }
  }
  return nrrd;
}

// The file's axes: the three (or fewer) that span the volume, in order, and the series axis of a
// 4D file (kNoAxis for fewer axes). With a space, the spatial axes are those with a direction;
// without one, the domain axes (time is one: a series with no other axis is along the last).
constexpr unsigned kNoAxis = ~0u;
struct Axes {
  unsigned spatial[3] = {kNoAxis, kNoAxis, kNoAxis};
  unsigned count = 0;  // spatial axes
  unsigned series = kNoAxis;
};

Axes axesOf(const Nrrd& header, const std::string& path) {
  Axes axes;
  if (header.dim < 4) {
    axes.count = header.dim;
    for (unsigned a = 0; a < header.dim; ++a) axes.spatial[a] = a;
    return axes;
  }
  unsigned index[NRRD_DIM_MAX] = {};
  unsigned n = header.spaceDim > 0 ? nrrdSpatialAxesGet(&header, index) : nrrdDomainAxesGet(&header, index);
  if (header.spaceDim == 0 && n == 4) n = 3;  // every axis a domain one: the last is the series
  if (n != 3)
    throw Error(path + ": NRRD has 4 axes of which " + std::to_string(n) + (header.spaceDim > 0 ? " have space directions" : " are domain axes") +
                "; isoatlas reads a 4D file as 3D volumes along one other axis");
  axes.count = 3;
  for (unsigned a = 0; a < 3; ++a) axes.spatial[a] = index[a];
  axes.series = 0 + 1 + 2 + 3 - index[0] - index[1] - index[2];
  return axes;
}

// Volume `t` of `nrrd`'s data (along axes.series) into v.data: a gather, the series axis at any place.
void copyVolume(const Nrrd& nrrd, const Axes& axes, std::int64_t t, Volume& v) {
  const std::size_t voxel = bytesPerVoxel(v.type);
  std::size_t stride[NRRD_DIM_MAX] = {};
  for (unsigned a = 0, s = 1; a < nrrd.dim; ++a) stride[a] = s, s *= nrrd.axis[a].size;
  const auto* src = static_cast<const std::byte*>(nrrd.data);
  v.data.resize(v.voxelCount() * voxel);
  if (axes.series == kNoAxis) {
    std::copy(src, src + v.data.size(), v.data.data());
    return;
  }
  const std::size_t base = std::size_t(t) * stride[axes.series];
  std::size_t out = 0;
  for (std::int64_t k = 0; k < v.dims[2]; ++k)
    for (std::int64_t j = 0; j < v.dims[1]; ++j)
      for (std::int64_t i = 0; i < v.dims[0]; ++i, out += voxel) {
        const std::size_t at = base + std::size_t(i) * stride[axes.spatial[0]] + std::size_t(j) * stride[axes.spatial[1]] +
                               std::size_t(k) * stride[axes.spatial[2]];
        std::copy(src + at * voxel, src + (at + 1) * voxel, v.data.data() + out);
      }
}

}  // namespace

Volume readNrrd(const std::string& path, std::int64_t volume) {
  Volume v;
  Axes axes;
  {
    // Check the header before teem allocates the data it announces.
    NrrdPtr header = load(path, true);
    if (header->dim < 1 || header->dim > 4)
      throw Error(path + ": NRRD has " + std::to_string(header->dim) + " axes; isoatlas reads 3D scalar volumes, or one volume of a 4D series");
    if (!scalarTypeFromNrrd(header->type, v.type))
      throw Error(path + ": unsupported NRRD type " + airEnumStr(nrrdType, header->type));
    axes = axesOf(*header, path);
    const std::int64_t volumes = axes.series == kNoAxis ? 1 : std::int64_t(header->axis[axes.series].size);
    requireVolumeIndex(path, volumes, volume);
    for (unsigned a = 0; a < 3; ++a) v.dims[a] = a < axes.count ? std::int64_t(header->axis[axes.spatial[a]].size) : 1;
    validateVolumeHeader(v, path);
    // teem reads the whole series: it must fit too.
    if (volumes > 1) {
      Volume series = v;
      series.dims[2] *= volumes;
      validateVolumeHeader(series, path + " (all " + std::to_string(volumes) + " volumes, as teem reads them)");
    }
  }
  NrrdPtr nrrd = load(path, false);
  if (!nrrd->data) throw Error(path + ": NRRD file has no data");

  Mat3 linear;
  Vec3 origin{0, 0, 0};
  if (nrrd->spaceDim > 0) {
    if (nrrd->spaceDim != 3) throw Error(path + ": NRRD space dimension is " + std::to_string(nrrd->spaceDim) + ", not 3");
    for (unsigned a = 0; a < 3; ++a) {
      for (int r = 0; r < 3; ++r) {
        const double d = a < axes.count ? nrrd->axis[axes.spatial[a]].spaceDirection[r] : (r == int(a) ? 1.0 : 0.0);
        linear.m[r][a] = std::isfinite(d) ? d : (r == int(a) ? 1.0 : 0.0);  // NaN: axis without direction
      }
    }
    for (int r = 0; r < 3; ++r) origin[r] = std::isfinite(nrrd->spaceOrigin[r]) ? nrrd->spaceOrigin[r] : 0.0;
    const int s = nrrd->space;
    const bool flipX = s == nrrdSpaceLeftPosteriorSuperior || s == nrrdSpaceLeftAnteriorSuperior || s == nrrdSpaceScannerXYZ;
    const bool flipY = s == nrrdSpaceLeftPosteriorSuperior || s == nrrdSpaceScannerXYZ;
    for (int c = 0; c < 3; ++c) {
      if (flipX) linear.m[0][c] = -linear.m[0][c];
      if (flipY) linear.m[1][c] = -linear.m[1][c];
    }
    if (flipX) origin.x = 0.0 - origin.x;  // not -0 at 0
    if (flipY) origin.y = 0.0 - origin.y;
  } else {
    for (unsigned a = 0; a < 3; ++a) {
      const double sp = a < axes.count ? nrrd->axis[axes.spatial[a]].spacing : 1.0;
      linear.m[a][a] = std::isfinite(sp) && sp > 0 ? sp : 1.0;
    }
  }
  setGeometryFromAffine(v, linear, origin, path);
  validateVolumeHeader(v, path);
  copyVolume(*nrrd, axes, std::max<std::int64_t>(volume, 0), v);
  return v;
}

void writeNrrd(const std::string& path, const Volume& v) {
  NrrdPtr nrrd(nrrdNew());
  std::size_t sizes[3] = {std::size_t(v.dims[0]), std::size_t(v.dims[1]), std::size_t(v.dims[2])};
  // teem only reads from the wrapped pointer while saving.
  if (nrrdWrap_nva(nrrd.get(), const_cast<std::byte*>(v.data.data()), nrrdTypeOf(v.type), 3, sizes))
    throw Error(path + ": teem could not wrap the volume: " + teemError(), ErrorKind::Failure);
  nrrdSpaceSet(nrrd.get(), nrrdSpaceLeftPosteriorSuperior);
  double dirs[NRRD_DIM_MAX][NRRD_SPACE_DIM_MAX] = {};
  for (int a = 0; a < 3; ++a)
    for (int r = 0; r < 3; ++r) dirs[a][r] = v.direction.m[r][a] * v.spacing[a] * (r < 2 ? -1.0 : 1.0);
  nrrdAxisInfoSet_nva(nrrd.get(), nrrdAxisInfoSpaceDirection, dirs);
  const double origin[3] = {-v.origin.x, -v.origin.y, v.origin.z};
  nrrdSpaceOriginSet(nrrd.get(), origin);
  int kinds[3] = {nrrdKindDomain, nrrdKindDomain, nrrdKindDomain};
  nrrdAxisInfoSet_nva(nrrd.get(), nrrdAxisInfoKind, kinds);

  std::unique_ptr<NrrdIoState, IoDeleter> io(nrrdIoStateNew());
  if (nrrdEncodingGzip->available()) nrrdIoStateEncodingSet(io.get(), nrrdEncodingGzip);
  const int rc = nrrdSave(path.c_str(), nrrd.get(), io.get());
  nrrd->data = nullptr;  // ours, not teem's to free
  if (rc) throw Error(path + ": could not write NRRD: " + teemError(), ErrorKind::Failure);
}

}  // namespace isoatlas

// The .isoatlas model file, version 4: what `isoatlas build` makes and eval, render and the viewer
// read. Little-endian on every machine (written and read byte by byte), integers unsigned unless
// said, reals IEEE 754.
//   magic "ISOATLAS" (8 bytes), format version (u32 = 4), then sections until the end of the file,
//   each: tag (4 ASCII bytes), payload length (u64), CRC-32 of the payload (u32, zlib's), payload.
//   HEAD  chart size N (u32, 2^k + 1); the charts' coincident_texels and gap_texels (u64 x 2); the
//         largest distance quantisation moved a position (f64, mm)
//   BASE  base vertex count (u64), per vertex position (f64 x 3) and dense vertex (i64, -1 when
//         made by a split); triangle count (u64), corners (u32 x 3, counter-clockwise); tile count
//         (u64), tiles (u32 x 2: the two triangles)
//   HALF  the specialised halfedge at the base level: per base triangle and corner k, the halfedge
//         from corner k to k + 1: chart index (u32) and start and end (u, v) in texels (u8 x 4);
//         then per base vertex its level (u8, 0 at the base). Must agree with BASE's tiles.
//   ATLS  chart count, columns, rows (u32 x 3; charts = tiles, columns x rows slots hold them),
//         then per chart (quantised_atlas.h): its box's low corner and step (f32 x 3 each), the
//         length of its packed codes (u32), its packed codes (packChartCodes: zlib's deflate of
//         N x N position codes, 12 bits in u16 x 3 (a reader takes up to 16): lo + code * step,
//         row by row, and N x N normals, u8 x 2, octahedral; each channel's residual from the
//         parallelogram prediction, in byte planes). Shared sides are taken from the lower-numbered chart and corners are their base
//         vertices, so borders come back identical.
//   DETL  (only where detail was stamped) detail chart count and size M (u32 x 2; M = 2^k + 1 above
//         N), then per detail chart in increasing tile order: its tile (u32), M x M positions
//         (f32 x 3), M x M normals (i16 x 3)
//   DENS  (only with --keep-dense) the dense mesh: vertex count (u64), positions (f64 x 3),
//         triangle count (u64), corners (u32 x 3)
//   PARA  (with DENS) per dense vertex its base triangle (u32) and barycentric weights (f64 x 3)
// Unknown tags are skipped (their checksum still checked). Still read: version 3 files (the same,
// but each chart's codes as they are: N x N u16 x 3 positions of 16 bits, then N x N u8 x 2
// normals) and version 2 files (the same, but HEAD without the quantisation error and ATLS as the
// whole atlas image: f32 x 3 positions, then i16 x 3 signed normalised normals, row-major from the
// top). Version 1 files (no atlas) are refused with a line saying to rebuild them.
#pragma once
#include <string>

#include "atlas/atlas.h"
#include "atlas/quantised_atlas.h"
#include "core/mesh.h"
#include "multires/base_mesh.h"

namespace isoatlas::atlas {

inline constexpr std::uint32_t kModelVersion = 4;

struct Model {
  std::uint32_t chartSize = 33;
  std::uint64_t coincidentTexels = 0, gapTexels = 0;  // as makeAtlas counted them
  double quantisationError = 0;  // as the file's writer measured it (0 for a version 2 file)
  multires::BaseMesh base;  // its parametrisation (denseTriangle, denseBary) only with the dense mesh
  Atlas atlas;
  Mesh dense;  // empty unless kept
  // The atlas's codes as a version-3 or 4 file held them (empty for a model built here): written back
  // as they are, with the file's quantisation error, while the atlas is still what they decode to,
  // so that a model read and saved keeps its bytes.
  std::vector<QuantisedChart> codes;
};

// The halfedge attributes HALF stores: per base triangle and corner k, the halfedge from corner k
// to k + 1 on its tile's chart.
struct BaseHalfedge {
  std::uint32_t chart;
  std::array<std::uint8_t, 4> uv;  // start u, v and end u, v in texels
  bool operator==(const BaseHalfedge&) const = default;
};
std::vector<BaseHalfedge> baseHalfedges(const multires::BaseMesh& base, std::uint32_t chartSize);

// Throws Error(BadInput) for a model the reader would refuse, before touching the file. Returns the
// largest distance (mm) quantising the atlas moved a position (what a reader will get back).
double writeModel(const std::string& path, const Model& model);

struct ModelReadOptions {
  bool checksums = true;  // false only for fuzzing, so that damaged payloads reach the parsers
};
// Checks the checksums, every count against the bytes its section holds, every index against its
// range and that reals are finite; throws Error(BadInput) naming the file, the section and the byte
// offset.
Model readModel(const std::string& path, const ModelReadOptions& options = {});

// Bytes of the dense mesh as a plain halfedge mesh, as the paper counts it: per vertex its position
// (f32 x 3) and one halfedge (u32); per halfedge its vertex, next, opposite and face (u32 x 4); per
// face one halfedge (u32).
std::uint64_t halfedgeMeshBytes(const Mesh& mesh);

// Bytes of the dense mesh as a binary PLY file's body (its header of a few hundred bytes aside): per
// vertex its position (f32 x 3), per face its corner count (u8) and corners (i32 each).
std::uint64_t binaryPlyBytes(const Mesh& mesh);

}  // namespace isoatlas::atlas

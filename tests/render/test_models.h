// Small multiresolution models for the viewer's tests, built as `isoatlas build` builds them.
#pragma once
#include "atlas/make_atlas.h"
#include "atlas/model_file.h"
#include "multires/stellar_simplify.h"
#include "multires/triangle_pairing.h"

namespace isoatlas::test {

inline atlas::Model buildModel(Mesh dense, double ratio, std::uint32_t chartSize) {
  atlas::Model m;
  m.chartSize = chartSize;
  m.base = multires::simplifyStellar(dense, {.vertexRatio = ratio});
  multires::pairTriangles(m.base, dense);
  m.atlas = atlas::makeAtlas(dense, m.base, chartSize);
  return m;
}

}  // namespace isoatlas::test

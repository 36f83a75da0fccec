#include <algorithm>
#include <cmath>

#include "atlas/atlas.h"
#include "core/error.h"

namespace isoatlas::atlas {

AtlasLayout packCharts(std::uint32_t charts, std::uint32_t chartSize) {
  require(charts > 0, "atlas: no charts to pack");
  AtlasLayout best{chartSize, charts, charts, 1};
  std::uint64_t bestSlots = ~0ull;
  std::uint32_t bestSkew = ~0u;
  // Every column count whose grid keeps the aspect ratio within 2; one row always fits 1 or 2 charts.
  for (std::uint32_t columns = 1; columns <= charts; ++columns) {
    const std::uint32_t rows = (charts + columns - 1) / columns;
    if (columns > 2 * std::uint64_t(rows) || rows > 2 * std::uint64_t(columns)) continue;
    const std::uint64_t slots = std::uint64_t(columns) * rows;
    const std::uint32_t skew = columns > rows ? columns - rows : rows - columns;
    if (slots < bestSlots || (slots == bestSlots && skew < bestSkew)) {
      best = {chartSize, charts, columns, rows};
      bestSlots = slots, bestSkew = skew;
    }
  }
  return best;
}

}  // namespace isoatlas::atlas

#include "edit/dvt/tree_rules.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <functional>

#include "core/gl/program.h"

namespace isoatlas::edit::dvt {

InputVoxel inputVoxel(const Cell& c, float value) {
  const auto packed = packCell(c);
  return {packed[0], packed[1], value, 0};
}

std::uint64_t preOrderKey(const Cell& c) {
  std::uint64_t key = 0;
  for (std::uint32_t d = 0; d < c.depth; ++d) key |= std::uint64_t(childTowards(c, d)) << (kMaxDepth - 1 - int(d));
  return key;
}

namespace {
std::uint64_t keyOf(const InputVoxel& v) { return preOrderKey(unpackCell(v.xy, v.zd)); }
}  // namespace

bool inPreOrder(const std::vector<InputVoxel>& input) {
  // Consecutive disjoint cells are in pre-order when the first lies in the lower half where their
  // paths part (keys not computed: this runs on every write).
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(1, std::max<std::size_t>(input.size(), 1), 4096), true,
      [&](const tbb::blocked_range<std::size_t>& r, bool ordered) {
        for (std::size_t i = r.begin(); ordered && i < r.end(); ++i) {
          const Cell a = unpackCell(input[i - 1].xy, input[i - 1].zd), b = unpackCell(input[i].xy, input[i].zd);
          const std::uint32_t d = commonDepth(a, b);
          ordered = d != a.depth && d != b.depth && childTowards(a, d) == 0;
        }
        return ordered;
      },
      std::logical_and<>());
}

PreOrderInput::PreOrderInput(std::vector<InputVoxel> voxels) : voxels_(std::move(voxels)) {
  if (!inPreOrder(voxels_))
    tbb::parallel_sort(voxels_.begin(), voxels_.end(), [](const InputVoxel& a, const InputVoxel& b) { return keyOf(a) < keyOf(b); });
}

std::vector<float> childScales(const TreeFrame& frame) {
  std::vector<float> s(kMaxDepth + 1);
  for (std::uint32_t d = 0; d <= std::uint32_t(kMaxDepth); ++d) s[d] = float(frame.radius(d) / frame.radius(d + 1));
  return s;
}

std::vector<std::pair<std::string, std::string>> ruleDefines() {
  return {{"MAX_DEPTH", std::to_string(kMaxDepth)},     {"NONE", std::to_string(kNone)},
          {"INSIDE", gl::glslFloat(kInside)},
          {"OUTSIDE", gl::glslFloat(kOutside)},         {"MARK_NONE", std::to_string(kMarkNone) + "u"},
          {"MARK_EXPAND", std::to_string(kMarkExpand) + "u"}, {"MARK_REDUCE", std::to_string(kMarkReduce) + "u"},
          {"MARK_COLLAPSE", std::to_string(kMarkCollapse) + "u"}, {"OP_UNION", std::to_string(unsigned(Op::Union)) + "u"},
          {"EXPAND_LEVELS", std::to_string(kExpandLevels) + "u"}};
}

}  // namespace isoatlas::edit::dvt

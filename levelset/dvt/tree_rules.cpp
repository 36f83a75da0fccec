#include "levelset/dvt/tree_rules.h"

#include "core/gl/program.h"

namespace isoatlas::levelset::dvt {

InputVoxel inputVoxel(const Cell& c, float value) {
  const auto packed = packCell(c);
  return {packed[0], packed[1], value, 0};
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
          {"MARK_COLLAPSE", std::to_string(kMarkCollapse) + "u"}, {"OP_UNION", std::to_string(unsigned(Op::Union)) + "u"}};
}

}  // namespace isoatlas::levelset::dvt

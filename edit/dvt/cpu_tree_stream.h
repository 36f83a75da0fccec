// The CPU tree (cpu_tree_passes.cpp) to and from the one pre-order stream (volume_tree.h): the stream
// cut at the brick depth into the top index (cpu_tree_top.h) and its bricks (cpu_brick.h), and spliced
// back, equal to the GPU's stream node for node.
#pragma once
#include <cstdint>

#include "edit/dvt/cpu_tree_top.h"
#include "edit/dvt/volume_tree.h"

namespace isoatlas::edit::dvt::cpu {

// Cuts `tree` at brickDepth into `top` (its items[0], the root, already there) and `bricks`; adds
// the nodes each holds to topNodes and brickNodes.
void loadStream(const VolumeTree& tree, std::uint32_t brickDepth, PairPool<TopNode>& top, PairPool<Brick>& bricks,
                std::uint64_t& topNodes, std::uint64_t& brickNodes);

// Appends the top from its root, and the bricks under it, to `out` in pre-order.
void appendStream(VolumeTree& out, std::uint32_t brickDepth, const PairPool<TopNode>& top, const PairPool<Brick>& bricks);

}  // namespace isoatlas::edit::dvt::cpu

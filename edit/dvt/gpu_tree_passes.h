// GpuTreePasses: the DVT passes (tree_passes.h) as GL 4.5 compute shaders (shaders/dvt_*.comp) in the
// context current when it is made (which must be current whenever it is used). The streams live in
// GPU buffers, ping-ponged by the restructure pass. A write runs as one chain of passes sized on the
// GPU (writeChained: the state, 96 bytes, comes back once at its end); driven pass by pass (the
// collapse, the node limit's iterations, TreeOptions::chainPasses = false) each pass's counters do.
#pragma once
#include <memory>

#include "core/gl/context.h"
#include "core/gl/shader_library.h"
#include "edit/dvt/tree_passes.h"

namespace isoatlas::edit::dvt {

std::unique_ptr<TreePasses> makeGpuTreePasses();  // in gl::Context::current()

// The GL buffers of a GPU tree, for renderers in the same context (render/dvt_render): the pointer
// stream (16 bytes per node) and the node stream (8 bytes per node), nodeCount() nodes.
struct GpuTreeBuffers {
  unsigned pointers = 0, cells = 0;
};
GpuTreeBuffers gpuTreeBuffers(const TreePasses& passes);  // throws unless `passes` are GPU passes
// The tree's shader files (edit/dvt/shaders/...), for renderers that include tree_layout.glsl.
const gl::EmbeddedShader* treeShaderFiles();

}  // namespace isoatlas::edit::dvt

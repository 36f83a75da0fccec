// run's pictures of the model through the tessellation renderer (the GL context current).
#pragma once
#include <nlohmann/json.hpp>

#include <string>

#include "atlas/model_file.h"
#include "pipeline/run_page.h"

namespace isoatlas::app {

// The model through the tessellation renderer, seen from the left: three levels of detail (CPU
// levels, no GPU refinement), the cascade with its wireframe (tile borders brown), and a turntable.
// Writes them into `products`, their figures into r["views"]; returns the stage's detail line.
std::string renderModelViews(const atlas::Model& model, pipeline::RunProducts& products, nlohmann::json& r);

}  // namespace isoatlas::app

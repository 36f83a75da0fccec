// Backend: where a GPU/CPU twin runs (the level set, marching cubes, the volume tree), and the one rule
// that turns --backend's word into it.
#pragma once
#include <array>
#include <string>

namespace isoatlas::levelset {

enum class Backend { Cpu, Gpu };

// The backend that --backend's "gpu", "cpu" or "auto" names, the GL at hand being a software
// rasteriser or not: auto takes the GPU unless its GL is software (llvmpipe). Throws Error (bad
// input) for another word. The command, the Python module and the window all choose by it.
Backend backendFor(const std::string& choice, bool softwareGl);
inline constexpr std::array<const char*, 3> kBackendChoices{"gpu", "cpu", "auto"};  // --backend's words
void requireBackendChoice(const std::string& choice);

}  // namespace isoatlas::levelset

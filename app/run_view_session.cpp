#include "app/run_view_session.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/atomic_file.h"

namespace isoatlas::app {

void writeViewSession(const std::string& path, const std::string& input, const Volume& volume, const levelset::SpeedParams& params,
                      const std::vector<pipeline::Ball>& seeds, int iterations, const std::string& startedFrom,
                      const std::vector<pipeline::EditStep>& edits, levelset::Topology topology, int iterationsAfterFill) {
  std::ostringstream out;
  out.precision(7);  // floats as they were given; world positions to well under a micrometre
  out << "# isoatlas run's segmentation and edits in the window: isoatlas view --script " << path << "\n"
      << "open " << std::filesystem::absolute(input).string() << "\nset t " << params.target << "\nset eps " << params.width
      << "\nset alpha " << params.alpha << "\n";
  if (topology == levelset::Topology::Preserve) out << "topology preserve\n";
  const double mmPerVoxel = std::cbrt(volume.spacing.x * volume.spacing.y * volume.spacing.z);  // as the window's radii
  if (startedFrom.empty()) {
    for (const pipeline::Ball& b : seeds) {
      const Vec3 w = volume.indexToWorld(b.centre);
      out << "seed " << w.x << "," << w.y << "," << w.z << "," << b.radius * mmPerVoxel << "\n";
    }
    out << "run " << iterations - iterationsAfterFill << "\n";
    if (topology == levelset::Topology::Preserve) out << "fill-threads\nrun " << iterationsAfterFill << "\n";
  } else {
    out << "# run's segmentation, which started from its solution at half resolution (the window steps at full resolution)\n"
        << "load-mask " << std::filesystem::absolute(startedFrom).string() << "\n";
  }
  for (const pipeline::EditStep& e : edits)
    out << (e.shape.starts_with("mesh:") ? "# (a mesh edit, not a brush) " : "") << "brush "
        << (e.op == edit::dvt::Op::Union ? "union " : "subtract ") << e.shape << "\n";
  out << "build\n";
  writeFileAtomically(path, out.str());
}

}  // namespace isoatlas::app

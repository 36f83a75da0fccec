// isoatlas probe VOLUME --at X,Y,Z --radius R: the statistics under a sphere and the level-set
// parameters they suggest (T = mean, eps = standard deviation), as JSON on stdout.
#include <cstdio>

#include "app/command.h"
#include "app/options.h"
#include "core/volume_io.h"
#include "levelset/probe.h"
#include "pipeline/segmentation.h"

namespace isoatlas::app {

void addProbeCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("probe", "mean and spread of a volume inside a sphere, and the T and eps they suggest");
  auto volume = std::make_shared<std::string>();
  auto at = std::make_shared<std::string>();
  auto radius = std::make_shared<double>(pipeline::kDefaultSeedRadius);
  sub->add_option("volume", *volume, "input volume (NIfTI, NRRD, INR, or a DICOM folder)")->required();
  sub->add_option("--at", *at, "centre X,Y,Z[,R] in voxel indices (R overrides --radius)")->required();
  sub->add_option("--radius", *radius, "radius in voxels")->capture_default_str()->check(inRange(kMinBallRadius, kMaxBallRadius));
  auto read = std::make_shared<VolumeReadOptions>();
  addVolumeReadOptions(*sub, *read);
  bindAction(*sub, [volume, at, radius, read](nlohmann::json& r) {
    const pipeline::Ball ball = parseBall(*at, "--at", *radius);
    const Volume v = readVolume(*volume, *read);
    pipeline::requireInside(v, ball.centre, "--at");
    const levelset::ProbeResult p = levelset::probeSphere(v, ball.centre, ball.radius);
    r["mean"] = p.mean;
    r["std"] = p.std;
    r["voxels"] = p.voxels;
    r["suggested_T"] = p.suggestedTarget();
    r["suggested_eps"] = p.suggestedWidth();
    nlohmann::json out = r;
    out.erase("command");
    std::printf("%s\n", out.dump().c_str());
    return 0;
  }, exitCode);
}

}  // namespace isoatlas::app

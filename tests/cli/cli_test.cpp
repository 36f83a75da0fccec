// End-to-end tests of the isoatlas command: exit codes, one-line errors, reports.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/mesh.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "core/volume_io.h"
#include "tests/multires/mesh_shapes.h"
#include "tests/test_util.h"

namespace isoatlas {
namespace {

struct Result {
  int code;
  std::string out, err;
};

Result run(const std::string& args) {
  // ctest runs tests in parallel: each process gets files of its own.
  static int calls = 0;
  const auto dir = std::filesystem::temp_directory_path() / "isoatlas-tests" / ("cli-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const auto out = dir / ("stdout" + std::to_string(++calls)), err = dir / ("stderr" + std::to_string(calls));
  const std::string cmd = std::string(ISOATLAS_EXE) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), test::readBytes(out), test::readBytes(err)};
}

std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

void expectBadInput(const std::string& args, const std::string& phrase) {
  const Result r = run(args);
  EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
  EXPECT_EQ(lines(r.err), 1u) << "one line on stderr: " << r.err;
  EXPECT_NE(r.err.find(phrase), std::string::npos) << r.err;
}

TEST(Cli, HelpForEverySubcommand) {
  for (const char* sub : {"info", "probe", "segment", "edit", "extract", "build", "eval", "render", "view", "run"}) {
    const Result r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
  }
}

TEST(Cli, UsageErrorsExitTwo) {
  expectBadInput("", "ubcommand is required");
  expectBadInput("frobnicate", "frobnicate");
  expectBadInput("info --no-such-option x.nii", "no-such-option");
  expectBadInput("info", "give a FILE");
}

TEST(Cli, ViewWithoutADisplaySaysSoAndExitsTwo) {
  const auto dir = test::scratchDir();
  const std::string mask = (dir / "m.nii.gz").string(), tree = (dir / "t.dvt").string();
  writeVolume(mask, test::rampVolume(ScalarType::UInt8, {8, 8, 8}));
  ASSERT_EQ(run("edit " + mask + " --union sphere:3,3,3,2 -o " + tree).code, 0);
  // The variables of a display unset, whatever the machine running the tests has.
  const std::string noDisplay = std::string(ISOATLAS_EXE) + " view " + tree + " --frames 2 --screenshot x.png";
  const auto err = dir / "view.err";
  const int status = std::system(("env -u DISPLAY -u WAYLAND_DISPLAY " + noDisplay + " 2>" + err.string()).c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2);
  const std::string message = test::readBytes(err);
  EXPECT_EQ(lines(message), 1u) << message;
  EXPECT_NE(message.find("needs a display"), std::string::npos) << message;
  expectBadInput("view " + (dir / "missing.dvt").string(), "missing.dvt");
  // A script is read whole before any window: a bad line is named, with or without a display.
  const auto script = dir / "actions.txt";
  std::ofstream(script) << "seed 1,2,3,4\nrun many\n";
  expectBadInput("view " + mask + " --script " + script.string(), "actions.txt:2: run");
  expectBadInput("view " + mask + " --size 10", "--size");
}

TEST(Cli, InfoOnAVolumeWritesAReport) {
  const auto dir = test::scratchDir();
  Volume v = test::rampVolume(ScalarType::Int16, {9, 8, 7});
  writeVolume((dir / "v.nii.gz").string(), v);
  const Result r = run("info " + (dir / "v.nii.gz").string() + " --report " + (dir / "r.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("9 x 8 x 7, int16"), std::string::npos) << r.out;
  const auto report = nlohmann::json::parse(test::readBytes(dir / "r.json"));
  EXPECT_EQ(report["dims"], nlohmann::json({9, 8, 7}));
  EXPECT_EQ(report["scalar_type"], "int16");
  EXPECT_DOUBLE_EQ(report["spacing"][1].get<double>(), 1.25);
  const ValueRange range = valueRange(v);
  EXPECT_DOUBLE_EQ(report["min"].get<double>(), range.min);
  EXPECT_DOUBLE_EQ(report["max"].get<double>(), range.max);
}

TEST(Cli, InfoOnAMeshReportsTopology) {
  const auto dir = test::scratchDir();
  writeMesh((dir / "torus.obj").string(), test::quadTorus(12, 8));
  const Result r = run("info " + (dir / "torus.obj").string() + " --report " + (dir / "r.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto report = nlohmann::json::parse(test::readBytes(dir / "r.json"));
  EXPECT_EQ(report["faces"], 96);
  EXPECT_EQ(report["closed"], true);
  EXPECT_EQ(report["manifold"], true);
  EXPECT_EQ(report["genus"], 1);
}

TEST(Cli, BadInputsExitTwoWithOneLine) {
  const auto dir = test::scratchDir();
  test::writeBytes(dir / "junk.nii", std::string(400, 'x'));
  expectBadInput("info " + (dir / "junk.nii").string(), "junk.nii");
  expectBadInput("info " + (dir / "missing.nrrd").string(), "no such file");
  std::string header = "#INRIMAGE-4#{\nXDIM=1000000\nYDIM=1000000\nZDIM=1000000\nVDIM=1\nTYPE=float\nPIXSIZE=32 bits\n";
  header.append(252 - header.size(), '\n');
  test::writeBytes(dir / "huge.inr", header + "##}\n");
  expectBadInput("info " + (dir / "huge.inr").string(), "more than the memory budget");
  Volume v = test::rampVolume(ScalarType::Float32);
  for (std::size_t n = 0; n < v.voxelCount(); ++n) v.setValue(n, std::nan(""));
  writeVolume((dir / "nan.nrrd").string(), v);
  expectBadInput("info " + (dir / "nan.nrrd").string(), "every voxel is NaN or infinite");
  test::writeBytes(dir / "empty.ply", "");
  expectBadInput("info " + (dir / "empty.ply").string(), "empty file");
  test::writeBytes(dir / "fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  const Result r = run("info " + (dir / "fin.off").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "isoatlas info: " + (dir / "fin.off").string() + ": not 2-manifold: edge (0, 1) is shared by 3 faces\n");
  EXPECT_NE(r.out.find("manifold no"), std::string::npos) << "the figures are still printed";
  test::writeBytes(dir / "truncated.nii.gz", test::readBytes(dir / "nan.nrrd").substr(0, 10));
  expectBadInput("info " + (dir / "truncated.nii.gz").string(), "truncated.nii.gz");
}

// A volume with NaN voxels (as resampled SPM and FSL outputs hold outside the field of view) is read:
// one line on stderr says how many were read as the background, and info counts them.
TEST(Cli, NanVoxelsAreReadAsTheBackgroundWithOneLine) {
  const auto dir = test::scratchDir();
  Volume v = test::rampVolume(ScalarType::Float32);
  v.setValue(5, std::nan(""));
  v.setValue(7, std::numeric_limits<double>::infinity());
  writeVolume((dir / "nan.nrrd").string(), v);
  const std::string report = (dir / "info.json").string();
  const Result r = run("info " + (dir / "nan.nrrd").string() + " --report " + report);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("nan.nrrd: 2 NaN or infinite voxels read as the background"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("2 NaN or infinite voxels"), std::string::npos) << r.out;
  EXPECT_EQ(nlohmann::json::parse(test::readBytes(report))["non_finite_voxels"], 2);
}

// Every subcommand's options with bad values (out of range, conflicting, a wrong extension, a missing,
// damaged or foreign file): exit 2, one line naming the option or the file, and nothing written.
TEST(Cli, EveryBadOptionExitsTwoNamingItAndWritesNothing) {
  const auto dir = test::scratchDir();
  const std::string d = dir.string() + "/";
  writeMesh(d + "torus.off", test::torusMesh(24, 12));
  writeMesh(d + "other.off", test::torusMesh(24, 12, 3, 1.5));  // the same vertex count, another shape
  writeVolume(d + "v.nii.gz", test::rampVolume(ScalarType::UInt8, {20, 20, 20}));
  ASSERT_EQ(run("build " + d + "torus.off -o " + d + "torus.isoatlas -q --no-hausdorff").code, 0);
  test::writeBytes(d + "damaged.isoatlas", test::readBytes(d + "torus.isoatlas").substr(0, 100));
  const std::filesystem::path out = dir / "out";
  std::filesystem::create_directories(out);
  const std::string o = out.string() + "/";
  const std::string model = d + "torus.isoatlas ", vol = d + "v.nii.gz ", seg = "segment " + vol + "-T 100 -e 10 --seed 10,10,10 ";
  const std::string stamp = "edit-detail " + model + "--text hi --radius 1 --depth 0.1 ";
  const struct {
    std::string args, phrase;
  } cases[] = {
      {"render " + model + "-o " + o + "r.png --cpu-error -1", "--cpu-error"},
      {"render " + model + "-o " + o + "r.png --gpu-pixels -3", "--gpu-pixels"},
      {"render " + model + "-o " + o + "r.png --cpu-error 2 --cpu-level 3", "--cpu-level excludes --cpu-error"},
      {"render " + model + "-o " + o + "r.png --turntable -2", "--turntable"},
      {"render " + model + "-o " + o + "r.png --frames 0", "--frames"},
      {"render " + model + "-o " + o + "r.png --smooth 99", "--smooth"},
      {"render " + d + "damaged.isoatlas -o " + o + "r.png", "damaged.isoatlas"},
      {"render " + model + "-o " + o + "r.png --max-memory 4K", "more than the memory budget of 4 KiB (--max-memory)"},
      {"info " + vol + "--max-memory lots", "--max-memory"},
      {"segment " + vol + "-T 100 -e 10 --seed 10,10,10 -o " + o + "s.nii.gz --max-memory 1K", "more than the memory budget of 1 KiB"},
      {"render " + model + "-o " + o + "r.jpg", "r.jpg"},
      {"render " + model + "--segmentation " + vol + "-o " + o + "r.png", "--segmentation"},
      {"build " + d + "torus.off -o " + o + "m.isoatlas --base-only " + o + "base.ply", "base.ply"},
      {"build " + d + "torus.off -o " + o + "m.isoatlas --max-error -1", "--max-error"},
      {"build " + d + "torus.off -o " + o + "m.isoatlas --base-vertices 0", "--base-vertices"},
      {"build " + d + "torus.off -o " + o + "m.isoatlas --base-vertices 100000000", "--base-vertices"},
      {"build " + d + "torus.off -o " + o + "m.isoatlas --chart 30", "--chart"},
      {"build " + d + "torus.off --base-only " + o + "b.obj --previews " + o + "p", "--previews"},
      {"build " + d + "torus.off -o " + o + "m.isoatlas --base-ratio 0.1 --base-vertices 20", "--base-ratio excludes --base-vertices"},
      {"eval " + model + "--dense " + d + "torus.off --out-mesh-level 2 " + o + "l.txt", "l.txt"},
      {"view " + model + "--screenshot " + o + "v.png", "--frames"},
      {"build " + d + "torus.off -o " + o + "m.isoatlas --relax-sweeps -1", "--relax-sweeps"},
      {"build " + d + "torus.off -o " + o + "m.txt", "m.txt"},
      {"build " + d + "missing.off -o " + o + "m.isoatlas", "missing.off"},
      {"edit " + vol + "-o " + o + "e.nii.gz --node-limit 0 --subtract sphere:0,0,0,3", "--node-limit"},
      {"edit " + vol + "-o " + o + "e.nii.gz --node-limit 3e9 --subtract sphere:0,0,0,3", "--node-limit"},
      {"edit " + vol + "-o " + o + "e.nii.gz --collapse-every -1 --subtract sphere:0,0,0,3", "--collapse-every"},
      {"edit " + vol + "-o " + o + "e.nii.gz --backend quantum --subtract sphere:0,0,0,3", "--backend"},
      {"edit " + vol + "-o " + o + "e.nii.gz --render " + o + "x.jpg --subtract sphere:0,0,0,3", "x.jpg"},
      {"edit " + vol + "-o " + o + "e.nii.gz --subtract blob:1,2", "blob:1,2"},
      {stamp + "--stamp " + d + "s.png --at 4,0,0 -o " + o + "d.isoatlas", "not both"},
      {stamp + "--at 100,100,100 -o " + o + "d.isoatlas", "--at"},
      {stamp + "--at 4,0,0 -o " + o + "d.ply", "d.ply"},
      {"eval " + model + "--dense " + d + "torus.off --samples 10", "--samples"},
      {"eval " + model + "--dense " + d + "torus.off --levels 4-2", "--levels"},
      {"eval " + model + "--dense " + d + "other.off", "other.off"},
      {"eval " + d + "damaged.isoatlas --dense " + d + "torus.off", "damaged.isoatlas"},
      {"eval " + model + "--dense " + d + "torus.off --out-mesh-level 99 " + o + "l.ply", "--out-mesh-level"},
      {seg + "-o " + o + "m.txt", "m.txt"},
      {seg + "-o " + o + "m.nii.gz --alpha 2", "alpha"},
      {seg + "-o " + o + "m.nii.gz --page 5", "--page"},
      {seg + "-o " + o + "m.nii.gz --half-resolution-start", "--converge"},
      {"segment " + vol + "-T 100 -e 10 --seed 100,0,0 -o " + o + "m.nii.gz", "--seed"},
      {"segment " + vol + "-T 100 -e -1 --seed 10,10,10 -o " + o + "m.nii.gz", "--width"},
      {"run " + vol + "-o " + o + "run --report " + o + "run/r.json --seed 100,0,0 -T 100 -e 10", "--seed"},
      {"run " + vol + "-o " + o + "run --report " + o + "elsewhere/r.json --seed 10,10,10 -T 100 -e 10", "elsewhere/r.json: its folder does not exist"},
      {"extract " + vol + "-o " + o + "s.txt", "s.txt"},
      {"extract " + vol + "-o " + o + "s.ply --smooth -1", "--smooth"},
      {"probe " + vol + "--at 100,100,100", "--at"},
      {"extract " + vol + "-o " + o + "no-such-folder/s.ply", "no-such-folder/s.ply: its folder does not exist"},
      {"run " + vol + "-o " + o + "run --chart 30", "--chart"},
      {"run " + vol + "-o " + o + "run --backend foo --seed 10,10,10 -T 100 -e 10", "--backend"},
      {"segment " + vol + "-T 100 -e 10 --seed 10,10,10,1e300 -o " + o + "m.nii.gz", "the radius must lie in [0.5, 1000]"},
      {"probe " + vol + "--at 10,10,10,0.01", "the radius must lie in [0.5, 1000]"},
      {"extract " + vol + "-o " + o + "s.ply --backend quantum", "--backend"},
      {"run " + vol + "-o " + o + "run --seed 10,10,10", "--seed needs --target"},
      {"run " + vol + "-o " + o + "run --relax-sweeps 5000", "--relax-sweeps"},
      {"run " + vol + "-o " + o + "run --seed 100,0,0 -T 100 -e 10", "--seed"},
  };
  for (const auto& c : cases) {
    expectBadInput(c.args, c.phrase);
    EXPECT_TRUE(std::filesystem::is_empty(out)) << "left output behind: " << c.args;
    std::filesystem::remove_all(out);
    std::filesystem::create_directories(out);
  }
}

TEST(Cli, InfoGlReportsOpenGL45OrLater) {
  const auto dir = test::scratchDir();
  const Result r = run("info --gl --report " + (dir / "gl.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto report = nlohmann::json::parse(test::readBytes(dir / "gl.json"));
  const std::string version = report["gl_version"];  // "major.minor": llvmpipe says 4.5, a GPU's driver 4.6
  const auto dot = version.find('.');
  ASSERT_NE(dot, std::string::npos) << version;
  EXPECT_GE(std::stoi(version.substr(0, dot)) * 10 + std::stoi(version.substr(dot + 1)), 45) << version;
  EXPECT_EQ(report["gl_contexts"], 1);
  EXPECT_GE(report["max_tessellation_level"].get<int>(), 64);
  EXPECT_FALSE(report["renderer"].get<std::string>().empty());
}

// A build killed (SIGKILL) while it writes its model leaves the old model whole: every file is written
// under a temporary name beside it and renamed only once complete (core/atomic_file.h).
TEST(Cli, AKilledBuildLeavesTheOldModelWhole) {
  const auto dir = test::scratchDir();
  const std::string mesh = (dir / "torus.off").string(), model = (dir / "torus.isoatlas").string();
  writeMesh(mesh, test::torusMesh(80, 32));
  ASSERT_EQ(run("build " + mesh + " -o " + model + " -q --no-hausdorff").code, 0);
  const std::string old = test::readBytes(model);
  // A second build with larger charts (a model of some 1 MB), killed once its temporary holds data.
  const pid_t pid = fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    std::freopen("/dev/null", "w", stderr);
    execl(ISOATLAS_EXE, ISOATLAS_EXE, "build", mesh.c_str(), "-o", model.c_str(), "-q", "--no-hausdorff", "--chart", "129",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  ASSERT_GT(pid, 0);
  // The temporary's size, or -1 while there is none.
  auto partialBytes = [&]() -> std::intmax_t {
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir))
      if (e.path().filename().string().find(".partial.torus.isoatlas") != std::string::npos) {
        const auto size = std::filesystem::file_size(e.path(), ec);
        return ec ? 0 : std::intmax_t(size);
      }
    return -1;
  };
  bool killed = false, exited = false;
  int status = 0;
  while (!killed && !exited) {
    if (partialBytes() > 0) killed = kill(pid, SIGKILL) == 0;
    else exited = waitpid(pid, &status, WNOHANG) == pid;
  }
  if (killed) waitpid(pid, &status, 0);
  ASSERT_TRUE(killed) << "the build ended before its model's temporary was seen";
  ASSERT_TRUE(WIFSIGNALED(status)) << "the build was not killed";
  // Killed mid-write: the old model, byte for byte (or, had the rename won the race, the whole new one).
  const std::string after = test::readBytes(model);
  if (after == old) {
    EXPECT_GT(partialBytes(), 0) << "killed with part of the new model written";
  } else {
    EXPECT_EQ(partialBytes(), -1) << "the model was replaced, yet its temporary is still there";
    EXPECT_EQ(run("eval " + model + " --dense " + mesh + " --levels 0 --samples 2000 -q").code, 0) << "a torn model";
  }
  // A finished build replaces it whole.
  ASSERT_EQ(run("build " + mesh + " -o " + model + " -q --no-hausdorff --chart 17").code, 0);
  EXPECT_NE(test::readBytes(model), old);
  EXPECT_EQ(run("eval " + model + " --dense " + mesh + " --levels 0 --samples 2000 -q").code, 0);
}

TEST(Cli, RunWritesItsProductsAndNamesSkippedStages) {
  const auto dir = test::scratchDir();
  Volume v = test::rampVolume(ScalarType::UInt8, {24, 20, 16});
  writeVolume((dir / "v.nii.gz").string(), v);
  const Result r = run("run " + (dir / "v.nii.gz").string() + " -o " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out/index.html"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out/input_slices.png"));
  const auto report = nlohmann::json::parse(test::readBytes(dir / "out/report.json"));
  bool sawSkipped = false;
  double stageSeconds = 0;
  for (const auto& s : report["stages"]) {
    sawSkipped |= s["status"] == "skipped";
    ASSERT_TRUE(s.contains("seconds")) << s["name"];
    EXPECT_GE(s["seconds"].get<double>(), 0) << s["name"];
    stageSeconds += s["seconds"].get<double>();
  }
  EXPECT_TRUE(sawSkipped);
  // Each stage's seconds are its own: together no more than the run's.
  EXPECT_LE(stageSeconds, report["seconds"].get<double>());
  EXPECT_NE(test::readBytes(dir / "out/index.html").find("<th>seconds</th>"), std::string::npos);
  EXPECT_NE(r.err.find("skipping"), std::string::npos);
}

// A bright torus (200) in a background of 50, ring radius 10 and tube radius 4 around (21,18,14), on a
// 44 x 40 x 28 grid with spacing and origin; its truth as a mask.
std::pair<std::filesystem::path, Volume> torusVolume(const std::filesystem::path& dir) {
  Volume v = Volume::zeros({44, 40, 28}, ScalarType::UInt8);
  v.spacing = {0.8, 0.8, 1.1};
  v.origin = {-17, -15, -14};
  Volume truth = Volume::zeros(v.dims, ScalarType::UInt8);
  for (std::int64_t z = 0; z < 28; ++z)
    for (std::int64_t y = 0; y < 40; ++y)
      for (std::int64_t x = 0; x < 44; ++x) {
        const double ring = std::hypot(x - 21.0, y - 18.0) - 10, d2 = ring * ring + (z - 14.0) * (z - 14.0);
        v.setValue(v.index(x, y, z), d2 < 16 ? 200 : 50);
        truth.setValue(truth.index(x, y, z), d2 < 16 ? 1 : 0);
      }
  writeVolume((dir / "torus.nii.gz").string(), v);
  return {dir / "torus.nii.gz", truth};
}

// The whole job on a phantom, on both backends: the segmentation against the truth, the surface
// closed with the torus's genus, every product written and named in report.json and index.html, one
// GL context for the solver, the extraction from its pages and the renders.
TEST(Cli, RunSegmentsExtractsAndRendersAPhantomOnBothBackends) {
  const auto dir = test::scratchDir();
  const auto [torus, truth] = torusVolume(dir);
  for (const std::string backend : {"cpu", "gpu"}) {
    SCOPED_TRACE(backend);
    const auto out = dir / backend;
    const Result r = run("run " + torus.string() + " -o " + out.string() + " --seed 31,18,14,2 --target 200 --width 60 " +
                         "--backend " + backend + " --samples 5000 --half-resolution-start --report " + (out / "run-report.json").string());
    ASSERT_EQ(r.code, 0) << r.err;
    // --report inside run's own -o folder, which did not exist before the run (a clean clone's demo).
    EXPECT_EQ(nlohmann::json::parse(test::readBytes(out / "run-report.json"))["command"], "run");
    const Volume mask = readVolume((out / "mask.nii.gz").string());
    std::int64_t both = 0, inMask = 0, inTruth = 0;
    for (std::size_t n = 0; n < mask.voxelCount(); ++n) {
      both += mask.value(n) == 1 && truth.value(n) == 1;
      inMask += mask.value(n) == 1;
      inTruth += truth.value(n) == 1;
    }
    EXPECT_GT(2.0 * double(both) / double(inMask + inTruth), 0.9) << "Dice with the phantom's truth";
    // The window's script of the same session: run segmented from its solution at half resolution
    // (--half-resolution-start), so the window takes its mask; the window reads it whole (and the volume it opens) before asking
    // for a display.
    const std::string session = test::readBytes(out / "view-session.txt");
    EXPECT_NE(session.find("load-mask " + std::filesystem::absolute(out / "mask.nii.gz").string() + "\n"), std::string::npos) << session;
    EXPECT_GT(nlohmann::json::parse(test::readBytes(out / "report.json"))["segment"]["half_resolution_iterations"].get<int>(), 0);
    const int viewed = std::system(("env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(ISOATLAS_EXE) + " view --script " +
                                    (out / "view-session.txt").string() + " 2>" + (dir / "view.err").string()).c_str());
    EXPECT_EQ(WEXITSTATUS(viewed), 2);
    EXPECT_NE(test::readBytes(dir / "view.err").find("needs a display"), std::string::npos) << test::readBytes(dir / "view.err");
    const MeshTopology t = analyzeTopology(readMesh((out / "surface.ply").string()));
    EXPECT_TRUE(t.closed && t.manifold) << t.firstProblem;
    EXPECT_EQ(t.genus, 1);
    EXPECT_EQ(t.components, 1u);

    const auto report = nlohmann::json::parse(test::readBytes(out / "report.json"));
    const std::string html = test::readBytes(out / "index.html");
    EXPECT_EQ(report["gl_contexts"], 1);
    EXPECT_EQ(report["segment"]["backend"], backend);
    EXPECT_EQ(report["extract"]["path"], backend + " pages");
    EXPECT_EQ(report["extract"]["genus"], 1);
    std::set<std::string> named;
    for (const auto& p : report["products"]) named.insert(p["file"].get<std::string>());
    for (const char* file : {"input_slices.png", "mask.nii.gz", "phi.nii.gz", "surface.ply", "surface.surf.gii", "surface.vtk", "surface_left.png",
                             "surface_top.png", "segmentation_slices.png", "model.isoatlas", "position_atlas.png",
                             "normal_atlas.png", "backfacing_atlas.png", "psnr_per_level.png", "model_level4_left.png", "render_level2.png",
                             "render_level4.png", "render_level10.png", "render_wire.png", "turntable_000.png", "turntable_007.png"}) {
      EXPECT_TRUE(named.count(file)) << file << " is not named in report.json";
      EXPECT_NE(html.find(std::string("href=\"") + file + "\""), std::string::npos) << file << " is not in index.html";
      EXPECT_GT(std::filesystem::file_size(out / file), 100u) << file;
    }
    EXPECT_EQ(named.size(), std::size_t(std::distance(std::filesystem::directory_iterator(out), {})) - 3)
        << "every file but report.json, index.html and the --report is a named product";
    // The model of the surface, measured at the even levels: closed like the surface, each finer
    // level at least as close as the base mesh.
    const auto& model = report["model"];
    EXPECT_EQ(model["model_bytes"], std::filesystem::file_size(out / "model.isoatlas"));
    ASSERT_EQ(model["levels"].size(), 6u);
    for (const auto& level : model["levels"]) {
      EXPECT_TRUE(level["closed"].get<bool>());
      EXPECT_GE(level["psnr_db"].get<double>(), model["levels"][0]["psnr_db"].get<double>() - 0.5);
    }
    // The tessellated views at CPU levels 2, 4 and 10 without GPU refinement: the levels' triangles.
    const auto& views = report["render"]["views"];
    ASSERT_EQ(views.size(), 4u);
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(views[k]["triangles"], model["levels"][std::size_t(std::vector<int>{1, 2, 5}[std::size_t(k)])]["triangles"]) << k;
  }
}

// run --topology preserve: the ball seeded in the phantom's ring stops as a sphere (the free run's
// surface has genus 1), and the window's script replays it: the topology, the steps, the threads'
// filling and the steps after it.
TEST(Cli, RunPreservingTheTopologyStopsTheRingAsASphere) {
  const auto dir = test::scratchDir();
  const auto [torus, truth] = torusVolume(dir);
  const auto out = dir / "kept";
  const Result r = run("run " + torus.string() + " -o " + out.string() + " --seed 31,18,14,2 --target 200 --width 60 " +
                       "--backend cpu --samples 5000 --levels 0,2 --topology preserve");
  ASSERT_EQ(r.code, 0) << r.err;
  const MeshTopology t = analyzeTopology(readMesh((out / "surface.ply").string()));
  EXPECT_TRUE(t.closed && t.manifold) << t.firstProblem;
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.components, 1u);
  const auto report = nlohmann::json::parse(test::readBytes(out / "report.json"));
  EXPECT_EQ(report["segment"]["topology"], "preserve");
  const std::string session = test::readBytes(out / "view-session.txt");
  EXPECT_NE(session.find("topology preserve\n"), std::string::npos) << session;
  EXPECT_NE(session.find("fill-threads\n"), std::string::npos) << session;
  // --space lps: surface.ply and .vtk in LPS (x and y negated, the tag saying so), the GIfTI in RAS as before.
  const auto lps = dir / "kept-lps";
  ASSERT_EQ(run("run " + torus.string() + " -o " + lps.string() + " --seed 31,18,14,2 --target 200 --width 60 " +
                "--backend cpu --samples 5000 --levels 0 --topology preserve --space lps").code, 0);
  const Mesh ras = readMesh((out / "surface.ply").string()), flipped = readMesh((lps / "surface.ply").string());
  ASSERT_EQ(ras.vertexCount(), flipped.vertexCount());
  for (std::size_t v = 0; v < ras.vertexCount(); ++v)
    ASSERT_EQ(flipped.positions[v], (Vec3{-ras.positions[v].x, -ras.positions[v].y, ras.positions[v].z})) << v;
  EXPECT_NE(test::readBytes(lps / "surface.vtk").find("SPACE=LPS"), std::string::npos);
  EXPECT_EQ(test::readBytes(lps / "surface.surf.gii"), test::readBytes(out / "surface.surf.gii"));
  const Result gifti = run("extract " + (out / "phi.nii.gz").string() + " --iso 0 --space lps -o " + (dir / "lps.surf.gii").string());
  EXPECT_EQ(gifti.code, 2);
  EXPECT_NE(gifti.err.find("a GIfTI surface is in RAS"), std::string::npos) << gifti.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "lps.surf.gii"));
  // With the half-resolution start: solved there with the topology kept too, so still a sphere.
  const auto half = dir / "kept-half";
  const Result h = run("run " + torus.string() + " -o " + half.string() + " --seed 31,18,14,2 --target 200 --width 60 " +
                       "--backend cpu --samples 5000 --levels 0 --topology preserve --half-resolution-start");
  ASSERT_EQ(h.code, 0) << h.err;
  const MeshTopology th = analyzeTopology(readMesh((half / "surface.ply").string()));
  EXPECT_TRUE(th.closed && th.manifold) << th.firstProblem;
  EXPECT_EQ(th.genus, 0) << "the start from half resolution lost the seed's topology";
  EXPECT_EQ(th.components, 1u);
  const auto halfReport = nlohmann::json::parse(test::readBytes(half / "report.json"));
  EXPECT_EQ(halfReport["segment"]["half_resolution_started"], true);
  EXPECT_GT(halfReport["segment"]["half_resolution_iterations"], 0);
}

// run's edit before extraction: a box cutting the phantom's ring leaves a closed surface of genus 0.
TEST(Cli, RunEditsTheSegmentationBeforeExtraction) {
  const auto dir = test::scratchDir();
  const auto [torus, truth] = torusVolume(dir);
  const auto out = dir / "edited";
  // The ring's centre is at (-0.2, -0.6, 1.4) mm and its radius 8 mm: the box cuts the tube at +x.
  const Result r = run("run " + torus.string() + " -o " + out.string() + " --seed 31,18,14,2 --target 200 --width 60 " +
                       "--backend cpu --samples 5000 --subtract box:4,-4,-20,14,3,20");
  ASSERT_EQ(r.code, 0) << r.err;
  const MeshTopology t = analyzeTopology(readMesh((out / "surface.ply").string()));
  EXPECT_TRUE(t.closed && t.manifold) << t.firstProblem;
  EXPECT_EQ(t.genus, 0) << "the ring is cut";
  const auto report = nlohmann::json::parse(test::readBytes(out / "report.json"));
  // Segmented from the seeds at full resolution, the window's script replays the seed (in world mm)
  // and the steps run took, then the edit as a brush.
  EXPECT_EQ(report["segment"]["half_resolution_iterations"], 0);
  const std::string session = test::readBytes(out / "view-session.txt");
  const Vec3 seedWorld = readVolume(torus.string()).indexToWorld({31, 18, 14});
  std::ostringstream seedLine;
  seedLine.precision(7);
  seedLine << "seed " << seedWorld.x << "," << seedWorld.y << "," << seedWorld.z << ",";
  EXPECT_NE(session.find(seedLine.str()), std::string::npos) << session;
  EXPECT_NE(session.find("run " + std::to_string(report["segment"]["iterations"].get<int>()) + "\n"), std::string::npos) << session;
  EXPECT_NE(session.find("brush subtract box:4,-4,-20,14,3,20\n"), std::string::npos) << session;
  EXPECT_EQ(report["extract"]["path"], "cpu dense") << "extracted from the edited tree";
  for (const char* key : {"nodes", "leaves", "depth_max", "seconds_write", "bytes", "backend"}) EXPECT_TRUE(report["edit"].contains(key)) << key;
  const Volume before = readVolume((out / "mask.nii.gz").string()), after = readVolume((out / "mask_edited.nii.gz").string());
  std::int64_t removed = 0, added = 0;
  for (std::size_t n = 0; n < before.voxelCount(); ++n) {
    removed += before.value(n) == 1 && after.value(n) == 0;
    added += before.value(n) == 0 && after.value(n) == 1;
  }
  EXPECT_GT(removed, 50);
  EXPECT_EQ(added, 0) << "a subtraction adds nothing";
  EXPECT_GT(readPng((out / "edited_tree.png").string()).width, 0);
  expectBadInput("run " + torus.string() + " -o " + out.string() + " --subtract ball:1,2,3", "a shape is sphere:");
}

// A 40x36x30 volume: a bright ball (200) of radius 9 around (20,18,15) in a background of 50.
std::filesystem::path ballVolume(const std::filesystem::path& dir) {
  Volume v = Volume::zeros({40, 36, 30}, ScalarType::UInt8);
  v.spacing = {0.9, 0.9, 1.2};
  v.origin = {-18, -16, -17};
  for (std::int64_t z = 0; z < 30; ++z)
    for (std::int64_t y = 0; y < 36; ++y)
      for (std::int64_t x = 0; x < 40; ++x) {
        const double d2 = (x - 20.0) * (x - 20.0) + (y - 18.0) * (y - 18.0) + (z - 15.0) * (z - 15.0);
        v.setValue(v.index(x, y, z), d2 < 81 ? 200 : 50);
      }
  writeVolume((dir / "ball.nii.gz").string(), v);
  return dir / "ball.nii.gz";
}

// `isoatlas probe` on ballVolume with the given options; its JSON.
nlohmann::json probeBall(const std::string& options) {
  const Result r = run("probe " + ballVolume(test::scratchDir()).string() + " " + options);
  EXPECT_EQ(r.code, 0) << r.err;
  return r.code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
}

TEST(Cli, ProbeSuggestsTheBallsIntensity) {
  const auto j = probeBall("--at 20,18,15 --radius 3");
  ASSERT_TRUE(j.contains("mean"));
  EXPECT_DOUBLE_EQ(j["mean"].get<double>(), 200);
  EXPECT_DOUBLE_EQ(j["std"].get<double>(), 0);
  EXPECT_DOUBLE_EQ(j["suggested_T"].get<double>(), 200);
  EXPECT_GT(j["voxels"].get<int>(), 100);
}

// R in --at X,Y,Z,R overrides --radius. Balls whose voxels are known by hand: radius 1 holds the
// centre and its 6 face neighbours, radius 1.5 adds the 12 edge neighbours (at sqrt 2), radius 1.8 the
// 8 corners (at sqrt 3). At (29,18,15), on the bright ball's edge (its voxels have d^2 < 81 from
// (20,18,15)), only the -x neighbour (28,18,15) is bright: 1 voxel of 200 and 6 of 50.
TEST(Cli, ProbeRadiusInTheCentreOverridesTheOption) {
  for (const auto& [radius, voxels] : {std::pair{"1", 7}, {"1.5", 19}, {"1.8", 27}}) {
    const auto j = probeBall(std::string("--at 20,18,15,") + radius + " --radius 5");
    ASSERT_TRUE(j.contains("voxels"));
    EXPECT_EQ(j["voxels"], voxels) << "radius " << radius;
    EXPECT_DOUBLE_EQ(j["mean"].get<double>(), 200);
  }
  const auto edge = probeBall("--at 29,18,15,1 --radius 5");
  ASSERT_TRUE(edge.contains("voxels"));
  EXPECT_EQ(edge["voxels"], 7);
  EXPECT_NEAR(edge["mean"].get<double>(), 500.0 / 7, 1e-9);
  EXPECT_NEAR(edge["std"].get<double>(), std::sqrt(135000.0) / 7, 1e-9);  // sqrt(55000/7 - (500/7)^2)
}

TEST(Cli, SegmentFindsTheBallAndKeepsTheGeometry) {
  const auto dir = test::scratchDir();
  const auto ball = ballVolume(dir);
  for (const char* backend : {"cpu", "gpu"}) {
    const std::string out = (dir / (std::string(backend) + ".nii.gz")).string();
    const Result r = run("segment " + ball.string() + " --seed 20,18,15,2 --target 200 --width 60 --alpha 0.8 " +
                         "--iterations 400 --converge --half-resolution-start --backend " + backend + " -o " + out + " --phi " +
                         (dir / "phi.nii").string() + " --report " + (dir / "r.json").string());
    ASSERT_EQ(r.code, 0) << r.err;
    const Volume mask = readVolume(out);
    const Volume input = readVolume(ball.string());
    EXPECT_EQ(mask.dims, input.dims);
    EXPECT_EQ(mask.type, ScalarType::UInt8);
    EXPECT_NEAR(mask.spacing.z, 1.2, 1e-6);
    EXPECT_NEAR(mask.origin.x, -18, 1e-5);
    std::int64_t inside = 0, wrong = 0;
    for (std::size_t n = 0; n < mask.voxelCount(); ++n) {
      inside += mask.value(n) == 1;
      wrong += (mask.value(n) == 1) != (input.value(n) == 200);
    }
    EXPECT_LT(double(wrong), 0.05 * double(inside)) << backend;
    const auto report = nlohmann::json::parse(test::readBytes(dir / "r.json"));
    for (const char* key : {"backend", "renderer", "iterations", "seconds", "steps_per_second", "converged",
                            "inside_voxels", "active_pages_peak", "active_pages_final", "physical_bytes_peak",
                            "readback_bytes_per_iteration", "half_resolution_iterations", "half_resolution_seconds"})
      EXPECT_TRUE(report.contains(key)) << key;
    EXPECT_GT(report["half_resolution_iterations"].get<int>(), 0) << "--half-resolution-start";
    EXPECT_EQ(report["backend"], backend);
    EXPECT_EQ(report["gl_contexts"], std::string(backend) == "gpu" ? 1 : 0);
    EXPECT_EQ(report["inside_voxels"], inside);
    EXPECT_EQ(report["converged"], true);
    if (std::string(backend) == "gpu") {
      EXPECT_GT(report["readback_bytes_per_iteration"].get<int>(), 0);
    }
    EXPECT_TRUE(std::filesystem::exists(dir / "phi.nii"));
  }
}

// An uncompressed NIfTI is read in place (mapped, page by page as the band reaches it): the mask is
// the compressed file's, read into memory; a file shorter than its header says is refused before any work.
TEST(Cli, SegmentReadsAnUncompressedNiftiInPlace) {
  const auto dir = test::scratchDir();
  const Volume ball = readVolume(ballVolume(dir).string());
  writeVolume((dir / "ball.nii").string(), ball);
  writeVolume((dir / "ball.nii.gz").string(), ball);
  const std::string args = " --seed 20,18,15,2 --target 200 --width 60 --alpha 0.8 --iterations 400 --converge --half-resolution-start";
  for (const char* name : {"ball.nii", "ball.nii.gz"}) {
    const Result r = run("segment " + (dir / name).string() + args + " -o " + (dir / (std::string(name) + ".mask.nii")).string() +
                         " --report " + (dir / (std::string(name) + ".json")).string());
    ASSERT_EQ(r.code, 0) << r.err;
  }
  const auto mapped = nlohmann::json::parse(test::readBytes(dir / "ball.nii.json"));
  EXPECT_EQ(mapped["volume_read"], "in place (mapped)");
  EXPECT_EQ(nlohmann::json::parse(test::readBytes(dir / "ball.nii.gz.json"))["volume_read"], "into memory");
  EXPECT_GT(mapped["inside_voxels"].get<int>(), 1000);
  EXPECT_EQ(readVolume((dir / "ball.nii.mask.nii").string()).data, readVolume((dir / "ball.nii.gz.mask.nii").string()).data);
  std::string bytes = test::readBytes(dir / "ball.nii");
  bytes.resize(bytes.size() - 100);
  test::writeBytes(dir / "short.nii", bytes);
  expectBadInput("segment " + (dir / "short.nii").string() + args + " -o " + (dir / "short.mask.nii").string(),
                 "short of the 43200 uint8 voxels");
  EXPECT_FALSE(std::filesystem::exists(dir / "short.mask.nii"));
}

TEST(Cli, SegmentRejectsBadInput) {
  const auto dir = test::scratchDir();
  const std::string ball = ballVolume(dir).string(), out = " -o " + (dir / "m.nii.gz").string();
  expectBadInput("segment " + ball + " --seed 80,18,15 --target 200 --width 60" + out, "lies outside the volume");
  expectBadInput("segment " + ball + " --seed 20,18,15 --target 200 --width 0" + out, "--width: '0' is not in [1e-06");
  expectBadInput("segment " + ball + " --seed 20,18,15 --target 200 --width 60 --alpha 1.5" + out, "--alpha: '1.5' is not in [0, 1]");
  expectBadInput("segment " + ball + " --seed 20,18 --target 200 --width 60" + out, "expected X,Y,Z");
  expectBadInput("segment " + ball + " --target 200 --width 60" + out, "give at least one --seed");
  expectBadInput("segment " + ball + " --seed 20,18,15 --target 200 --width 60 -o m.png", "unknown volume format");
  Volume nan = test::rampVolume(ScalarType::Float32);
  for (std::size_t n = 0; n < nan.voxelCount(); ++n) nan.setValue(n, std::nan(""));
  writeVolume((dir / "nan.nrrd").string(), nan);
  expectBadInput("segment " + (dir / "nan.nrrd").string() + " --seed 1,1,1 --target 1 --width 1" + out, "every voxel is NaN");
  test::writeBytes(dir / "empty.nii", "");
  expectBadInput("segment " + (dir / "empty.nii").string() + " --seed 1,1,1 --target 1 --width 1" + out, "empty.nii");
  expectBadInput("probe " + ball + " --at 20,18,99 --radius 2", "lies outside the volume");
}

// extract --space lps writes the RAS surface with x and y negated, the faces as they were.
TEST(Cli, ExtractWritesLpsOnRequest) {
  const auto dir = test::scratchDir();
  const std::string ball = ballVolume(dir).string(), ras = (dir / "ras.ply").string(), lps = (dir / "lps.ply").string();
  ASSERT_EQ(run("extract " + ball + " --iso 125 --backend cpu -o " + ras).code, 0);
  const Result r = run("extract " + ball + " --iso 125 --backend cpu --space lps -o " + lps);
  ASSERT_EQ(r.code, 0) << r.err;
  const Mesh a = readMesh(ras), b = readMesh(lps);
  ASSERT_EQ(a.vertexCount(), b.vertexCount());
  for (std::size_t v = 0; v < a.vertexCount(); ++v)
    ASSERT_TRUE(b.positions[v].x == -a.positions[v].x && b.positions[v].y == -a.positions[v].y && b.positions[v].z == a.positions[v].z) << v;
  EXPECT_EQ(a.faceVertices, b.faceVertices);
  expectBadInput("extract " + ball + " --space lsp -o " + lps, "--space");
}

TEST(Cli, ExtractGivesOneClosedSurfaceOnBothBackends) {
  const auto dir = test::scratchDir();
  const auto ball = ballVolume(dir);
  std::vector<nlohmann::json> reports;
  for (const char* backend : {"cpu", "gpu"}) {
    const std::string out = (dir / (std::string(backend) + ".ply")).string(), report = (dir / "x.json").string();
    const Result r = run("extract " + ball.string() + " --iso 125 --backend " + backend + " -o " + out + " --report " + report);
    ASSERT_EQ(r.code, 0) << r.err;
    reports.push_back(nlohmann::json::parse(test::readBytes(report)));
    const Mesh m = readMesh(out);
    EXPECT_EQ(m.faceCount(), reports.back()["triangles"].get<std::size_t>());
    EXPECT_EQ(reports.back()["gl_contexts"], std::string(backend) == "gpu" ? 1 : 0);
    EXPECT_EQ(reports.back()["path"], std::string(backend) + " dense");
    for (const char* key : {"vertices", "triangles", "components", "closed", "manifold", "euler", "genus", "seconds",
                            "cells_visited"})
      EXPECT_TRUE(reports.back().contains(key)) << key;
  }
  EXPECT_EQ(reports[0]["triangles"], reports[1]["triangles"]);
  EXPECT_EQ(reports[0]["vertices"], reports[1]["vertices"]);
  EXPECT_EQ(reports[1]["closed"], true);
  EXPECT_EQ(reports[1]["manifold"], true);
  EXPECT_EQ(reports[1]["genus"], 0);
  EXPECT_EQ(reports[1]["components"], 1);
}

TEST(Cli, ExtractRejectsBadInput) {
  const auto dir = test::scratchDir();
  const std::string ball = ballVolume(dir).string();
  expectBadInput("extract " + (dir / "missing.nii").string() + " -o a.ply", "no such file");
  expectBadInput("extract " + ball + " -o a.png", "write the mesh as .ply, .off, .obj, .vtk or .surf.gii");
  expectBadInput("extract " + ball + " --smooth -2 -o " + (dir / "a.ply").string(), "--smooth: '-2' is not in [0, 1000]");
  const Result r = run("extract " + ball + " --iso 1000 -o " + (dir / "a.ply").string());
  EXPECT_EQ(r.code, 1) << "no surface at that isovalue: the work fails";
  EXPECT_NE(r.err.find("no surface"), std::string::npos) << r.err;
}

TEST(Cli, BuildMakesATriquadBaseMeshAndAModel) {
  const auto dir = test::scratchDir();
  const std::string torus = (dir / "torus.off").string();
  writeMesh(torus, test::torusMesh(60, 30));
  const std::string model = (dir / "torus.isoatlas").string(), base = (dir / "base.obj").string(),
                    report = (dir / "r.json").string();
  const std::string previews = (dir / "previews").string();
  const Result r = run("build " + torus + " -o " + model + " --base-only " + base + " --base-ratio 0.03 --chart 17 --previews " +
                       previews + " --report " + report);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(test::readBytes(report));
  for (const char* key : {"dense_vertices", "base_vertices", "base_triangles", "tiles", "splits_for_matching",
                          "seconds_simplify", "seconds_match", "hausdorff_base", "psnr_base_db",
                          "hausdorff_dense_to_base", "hausdorff_base_to_dense", "bounding_box_diagonal",
                          "folded_dense_triangles", "refused_welds", "history_steps", "vertices_above_target",
                          "charts", "atlas_width", "atlas_height", "atlas_efficiency", "coincident_texels", "gap_texels",
                          "seconds_chart", "model_bytes", "dense_halfedge_bytes", "backfacing_texel_quads", "folded_texel_quads",
                          "folded_worst_chart_at"})
    EXPECT_TRUE(j.contains(key)) << key;
  // One chart per tile, packed into the slots the width and height hold.
  EXPECT_EQ(j["charts"], j["tiles"]);
  EXPECT_EQ(j["atlas_efficiency"].get<double>(), j["charts"].get<double>() * 17 * 17 / (j["atlas_width"].get<double>() * j["atlas_height"].get<double>()));
  EXPECT_EQ(j["model_bytes"], std::filesystem::file_size(model));
  for (const char* png : {"position_atlas.png", "normal_atlas.png", "backfacing_atlas.png"}) {
    const Image preview = readPng(std::filesystem::path(previews) / png);
    EXPECT_EQ(preview.width, j["atlas_width"].get<int>());
    EXPECT_EQ(preview.height, j["atlas_height"].get<int>());
  }
  // The symmetric distance is the larger side, and the PSNR follows from it and the diagonal.
  EXPECT_EQ(j["hausdorff_base"].get<double>(),
            std::max(j["hausdorff_dense_to_base"].get<double>(), j["hausdorff_base_to_dense"].get<double>()));
  EXPECT_NEAR(j["psnr_base_db"].get<double>(),
              20 * std::log10(j["bounding_box_diagonal"].get<double>() / j["hausdorff_base"].get<double>()), 1e-9);
  EXPECT_EQ(j["dense_vertices"], 1800);
  EXPECT_EQ(j["base_vertices"], 54);
  EXPECT_EQ(j["tiles"].get<int>() * 2, j["base_triangles"].get<int>());
  EXPECT_LT(j["hausdorff_base"].get<double>(), 0.5);
  // The charts sample through the exact history: no gaps, no place of the surface claimed twice.
  EXPECT_EQ(j["coincident_texels"], 0);
  EXPECT_EQ(j["gap_texels"], 0);
  EXPECT_EQ(j["border_disagreements"], 0);
  EXPECT_EQ(j["history_steps"].get<int>(), 1800 - 54);
  const Mesh quads = readMesh(base);
  EXPECT_TRUE(quads.allFacesHave(4));
  EXPECT_EQ(quads.faceCount(), j["tiles"].get<std::size_t>());
  const MeshTopology t = analyzeTopology(quads);
  EXPECT_TRUE(t.closed && t.manifold && t.oriented) << t.firstProblem;
  EXPECT_EQ(t.genus, 1);
  // Without --keep-dense the model holds no dense mesh: the base mesh and the atlas alone.
  EXPECT_LT(std::filesystem::file_size(model), j["atlas_width"].get<std::size_t>() * j["atlas_height"].get<std::size_t>() * 18 + 1800 * 24);
}

TEST(Cli, EvalMeasuresEveryLevelAgainstTheDenseMesh) {
  const auto dir = test::scratchDir();
  const std::string torus = (dir / "torus.off").string(), model = (dir / "torus.isoatlas").string();
  writeMesh(torus, test::torusMesh(60, 30));
  ASSERT_EQ(run("build " + torus + " -o " + model + " --base-ratio 0.03 --chart 9 --no-hausdorff").code, 0);
  const std::string report = (dir / "e.json").string(), plot = (dir / "psnr.png").string(), level = (dir / "l6.ply").string();
  const Result r = run("eval " + model + " --dense " + torus + " --plot " + plot + " --out-mesh-level 6 " + level +
                       " --samples 5000 --report " + report);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(test::readBytes(report));
  for (const char* key : {"atlas_efficiency", "atlas_width", "atlas_height", "charts", "model_bytes", "dense_halfedge_bytes",
                          "coincident_texels", "gap_texels", "quantisation_error", "dense_ply_bytes", "model_to_dense_halfedge"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["model_to_dense_halfedge"].get<double>(), j["model_bytes"].get<double>() / j["dense_halfedge_bytes"].get<double>());
  ASSERT_EQ(j["levels"].size(), 7u);  // chart 9: levels 0..6
  const double diagonal = j["bounding_box_diagonal"].get<double>();
  for (int l = 0; l <= 6; ++l) {
    const auto& f = j["levels"][l];
    EXPECT_EQ(f["level"], l);
    EXPECT_EQ(f["triangles"].get<std::size_t>(), j["charts"].get<std::size_t>() * (std::size_t(1) << l / 2 * 2) * (l % 2 ? 4 : 2));
    EXPECT_TRUE(f["closed"].get<bool>() && f["manifold"].get<bool>());
    EXPECT_NEAR(f["psnr_db"].get<double>(), 20 * std::log10(diagonal / f["hausdorff"].get<double>()), 1e-9);
    // The RMS of the same samples: never past the largest, so its PSNR is never below.
    EXPECT_NEAR(f["psnr_rms_db"].get<double>(), 20 * std::log10(diagonal / f["rms"].get<double>()), 1e-9);
    EXPECT_LE(f["rms"].get<double>(), f["hausdorff"].get<double>());
  }
  // Finer levels come closer: the finest beats the base mesh by a wide margin.
  EXPECT_GT(j["levels"][6]["psnr_db"].get<double>(), j["levels"][0]["psnr_db"].get<double>() + 10);
  const Mesh six = readMesh(level);
  EXPECT_EQ(six.faceCount(), j["levels"][6]["triangles"].get<std::size_t>());
  EXPECT_GT(readPng(plot).width, 0);
  expectBadInput("eval " + model + " --dense " + torus + " --levels 0-7", "--levels: '7' is not a level from 0 to 6");
  expectBadInput("eval " + model + " --dense " + torus + " --out-mesh-level 9 " + level, "--out-mesh-level: level 9");
  test::writeBytes(dir / "bad.isoatlas", test::readBytes(model).substr(0, 100));
  expectBadInput("eval " + (dir / "bad.isoatlas").string() + " --dense " + torus, "runs past the end");
}

TEST(Cli, BuildRejectsBadInput) {
  const auto dir = test::scratchDir();
  const std::string bowtie = (dir / "bowtie.off").string();
  test::writeBytes(bowtie, "OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n-1 0 0\n0 -1 0\n3 0 1 2\n3 0 3 4\n");
  const std::string torus = (dir / "torus.off").string();
  writeMesh(torus, test::torusMesh(12, 8));
  const std::string out = " -o " + (dir / "m.isoatlas").string();
  expectBadInput("build " + bowtie + out, "not 2-manifold");
  expectBadInput("build " + (dir / "missing.off").string() + out, "no such file");
  expectBadInput("build " + torus + out + " --chart 32", "--chart must be 2^k + 1");
  expectBadInput("build " + torus + out + " --chart 257", "--chart: '257' is not in [3, 129]");
  expectBadInput("build " + torus + out + " --chart 31", "--chart must be 2^k + 1");
  expectBadInput("build " + torus + out + " --base-ratio 0", "--base-ratio: '0' is not in [1e-06, 1]");
  expectBadInput("build " + torus + " -o " + (dir / "m.obj").string(), "must end in .isoatlas");
  expectBadInput("build " + torus, "give -o MODEL.isoatlas");
}

TEST(Cli, EditDetailEngravesAWordAndTheModelStaysClosed) {
  const auto dir = test::scratchDir();
  const std::string torus = (dir / "torus.off").string(), model = (dir / "torus.isoatlas").string();
  writeMesh(torus, test::torusMesh(60, 30));
  ASSERT_EQ(run("build " + torus + " -o " + model + " --base-ratio 0.03 --chart 9 --no-hausdorff").code, 0);
  const std::string out = (dir / "engraved.isoatlas").string(), report = (dir / "r.json").string(), png = (dir / "close.png").string();
  const Result r = run("edit-detail " + model + " --text Hi --at 4.1,0,0 --radius 1 --depth 0.1 --detail 33 -o " + out +
                       " --render " + png + " --report " + report);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(test::readBytes(report));
  EXPECT_GT(j["detail_tiles"].get<int>(), 0);
  EXPECT_GT(j["texels_changed"].get<int>(), 0);
  EXPECT_EQ(j["max_level"], 10);  // detail charts of 33 texels
  EXPECT_NEAR(j["normal"][0].get<double>(), 1, 0.05) << "the outer equator faces +x";
  EXPECT_GT(readPng(png).width, 0);
  // Every level of the engraved model, the detail levels too, is closed.
  const std::string evalReport = (dir / "e.json").string();
  ASSERT_EQ(run("eval " + out + " --dense " + torus + " --levels 6-10 --samples 2000 --report " + evalReport).code, 0);
  const auto evaluated = nlohmann::json::parse(test::readBytes(evalReport));
  for (const auto& level : evaluated["levels"])
    EXPECT_TRUE(level["closed"].get<bool>() && level["manifold"].get<bool>()) << level["level"];
  expectBadInput("edit-detail " + model + " --at 4,0,0 --radius 1 --depth 0.1 -o " + out, "give --stamp IMAGE.png or --text WORD");
  expectBadInput("edit-detail " + model + " --text Hi --at 4,0,0 --radius 1 --depth 0.1 --detail 9 -o " + out, "detail chart size");
  expectBadInput("edit-detail " + model + " --stamp " + (dir / "none.png").string() + " --at 4,0,0 --radius 1 --depth 0.1 -o " + out,
                 "none.png: no such file");
  test::writeBytes(dir / "text.png", "not a picture");
  expectBadInput("edit-detail " + model + " --stamp " + (dir / "text.png").string() + " --at 4,0,0 --radius 1 --depth 0.1 -o " + out,
                 "text.png: not a PNG file");
}

// A small mesh is its own base mesh by default: a cube's model lies on the cube at level 10 (to its codes'
// steps), and the capture of level 10 is a closed manifold; so is mpi's, whose sliver tiles join border
// texels in the codes until their side codes move apart (306 non-manifold edges before). One whose
// tiles put two texels at one place in the atlas itself (corner_poly: coincident texels) is simplified
// instead, and its level 10 stays a manifold.
TEST(Cli, ASmallMeshIsItsOwnBaseWhereItsTilesSampleCleanly) {
  const auto dir = test::scratchDir();
  Mesh cube;
  cube.positions = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
  for (const auto& q : std::vector<std::array<std::uint32_t, 4>>{{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}})
    cube.addFace({q[0], q[1], q[2]}), cube.addFace({q[0], q[2], q[3]});
  // The cube with a vertex in the middle of an edge and a triangle of no area along it: its tile
  // samples two texels at one place, so it is simplified instead.
  Mesh sliver;
  sliver.positions = cube.positions;
  sliver.positions.push_back({0, -1, -1});
  for (const auto& t : std::vector<std::array<std::uint32_t, 3>>{{0, 3, 2}, {0, 2, 1}, {0, 1, 8}, {8, 1, 5}, {8, 5, 4}, {8, 4, 0}, {4, 5, 6},
                                                                 {4, 6, 7}, {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}})
    sliver.addFace({t[0], t[1], t[2]});
  const std::string meshes = std::string(ISOATLAS_DATA) + "/meshes/";
  if (!std::filesystem::exists(meshes + "mpi.off")) GTEST_SKIP() << "run scripts/fetch-data for " << meshes;
  writeMesh((dir / "cube.off").string(), cube);
  writeMesh((dir / "sliver.off").string(), sliver);
  // mpi and corner_poly: polygon files, whole only where their non-convex polygons split without a
  // triangle turned over (core/polygon_triangulation.h).
  for (const auto& [name, whole] : {std::pair{std::string("cube"), true}, {std::string("mpi"), true}, {std::string("corner_poly"), true},
                                    {std::string("sliver"), false}}) {
    const std::string mesh = name == "cube" || name == "sliver" ? (dir / (name + ".off")).string() : meshes + name + ".off";
    const std::string model = (dir / (name + ".isoatlas")).string();
    const std::string built = (dir / (name + "_build.json")).string(), rendered = (dir / (name + "_render.json")).string();
    ASSERT_EQ(run("build " + mesh + " -o " + model + " -q --no-hausdorff --report " + built).code, 0) << name;
    const auto b = nlohmann::json::parse(test::readBytes(built));
    EXPECT_EQ(b["base_whole"].get<bool>(), whole) << name;
    // Kept whole, each tile is two of the mesh's triangles: its uniform grid lies on them, unfolded
    // (relaxed by the default 8 sweeps, corner_poly folded 6 quads; mpi, its polygons split with
    // slivers, 349).
    EXPECT_EQ(b["relax_sweeps"].get<int>(), whole ? 0 : 8) << name;
    if (whole) {
      EXPECT_EQ(b["folded_texel_quads"].get<std::uint64_t>(), 0u) << name;
    }
    const Result r = run("render " + model + " --cpu-level 0 --gpu-level 5 --size 64,48 -o " + (dir / (name + ".png")).string() +
                         " --capture " + (dir / (name + ".ply")).string() + " --report " + rendered);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(test::readBytes(rendered));
    EXPECT_TRUE(j["captured_closed"].get<bool>()) << name << ": " << j["captured_non_manifold_edges"] << " non-manifold edges";
  }
  const std::string report = (dir / "eval.json").string();
  ASSERT_EQ(run("eval " + (dir / "cube.isoatlas").string() + " --dense " + (dir / "cube.off").string() + " --levels 0,10 -q --report " + report).code, 0);
  const auto levels = nlohmann::json::parse(test::readBytes(report))["levels"];
  ASSERT_EQ(levels.size(), 2u);
  EXPECT_LT(levels[0]["hausdorff"].get<double>(), 1e-9) << "level 0 is the cube itself";
  EXPECT_LT(levels[1]["hausdorff"].get<double>(), 2.0 / 4095) << "level 10 lies on the cube to within a code step";
}

TEST(Cli, RenderDrawsAModelWithoutCracksAndAGridOfThem) {
  const auto dir = test::scratchDir();
  const std::string torus = (dir / "torus.off").string(), model = (dir / "torus.isoatlas").string();
  writeMesh(torus, test::torusMesh(60, 30));
  ASSERT_EQ(run("build " + torus + " -o " + model + " --base-ratio 0.03 --chart 9 --no-hausdorff").code, 0);
  const std::string png = (dir / "t.png").string(), capture = (dir / "t.ply").string(), report = (dir / "r.json").string();
  const Result r = run("render " + model + " --cpu-level 3 --gpu-level 1 --size 200,150 --wire --capture " + capture + " -o " + png +
                       " --report " + report);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(test::readBytes(report));
  for (const char* key : {"patches", "triangles", "cpu_ms", "gpu_ms", "frame_ms", "fps", "renderer"}) EXPECT_TRUE(j.contains(key)) << key;
  const Image image = readPng(png);
  EXPECT_EQ(image.width, 200);
  EXPECT_EQ(image.height, 150);
  // The GPU's triangles, welded by position: the torus closed, every triangle drawn captured.
  const Mesh captured = readMesh(capture);
  EXPECT_EQ(captured.faceCount(), j["triangles"].get<std::size_t>());
  EXPECT_EQ(analyzeTopology(captured).boundaryEdges, 0u);
  EXPECT_TRUE(j["captured_closed"].get<bool>());
  EXPECT_EQ(j["captured_unbalanced_edges"], 0);

  const std::string frames = (dir / "spin.png").string(), grid = (dir / "g.json").string();
  ASSERT_EQ(run("render " + model + " --turntable 3 --size 64,48 -o " + frames).code, 0);
  for (const char* name : {"spin_000.png", "spin_001.png", "spin_002.png"}) EXPECT_EQ(readPng((dir / name).string()).width, 64) << name;
  ASSERT_EQ(run("render " + model + " " + model + " --scene grid:3x3 --cpu-level 6 --size 160,90 --frames 2 -o " + png + " --report " + grid).code, 0);
  const auto g = nlohmann::json::parse(test::readBytes(grid));
  EXPECT_EQ(g["instances"], 9);
  EXPECT_EQ(g["cpu_levels"][1], 6);
  EXPECT_LT(g["cpu_levels"][0].get<int>(), 6) << "the far instances are coarser";
  EXPECT_GT(g["fps"].get<double>(), 0);

  // The smooth mode: OpenSubdiv's uniform level 2 makes 8 * 2^2 triangles a tile.
  const std::string smooth = (dir / "s.json").string();
  const std::string base = (dir / "b.json").string();
  ASSERT_EQ(run("render " + model + " --cpu-level 0 --gpu-level 0 --size 64,48 -o " + png + " --report " + base).code, 0);
  ASSERT_EQ(run("render " + model + " --smooth 2 --size 64,48 -o " + png + " --report " + smooth).code, 0);
  const std::size_t tiles = nlohmann::json::parse(test::readBytes(base))["patches"];  // level 0: a patch a tile
  EXPECT_EQ(nlohmann::json::parse(test::readBytes(smooth))["triangles"].get<std::size_t>(), 32 * tiles);
  // Its capture's cracks are reported as they are (the smooth mode is not crack-free by construction):
  // the figures must be those of the mesh written.
  const std::string smoothCapture = (dir / "s.ply").string();
  ASSERT_EQ(run("render " + model + " --smooth 2 --size 64,48 -o " + png + " --capture " + smoothCapture + " --report " + smooth).code, 0);
  const auto sj = nlohmann::json::parse(test::readBytes(smooth));
  const Mesh smoothMesh = readMesh(smoothCapture);
  const MeshTopology st = analyzeTopology(smoothMesh);
  std::size_t unbalanced = 0;
  for (const auto& [edge, balance] : directedEdgeBalance(smoothMesh)) unbalanced += balance != 0;
  EXPECT_EQ(sj["captured_triangles"], smoothMesh.faceCount());
  EXPECT_EQ(sj["captured_closed"], st.closed);
  EXPECT_EQ(sj["captured_boundary_edges"], st.boundaryEdges);
  EXPECT_EQ(sj["captured_unbalanced_edges"], unbalanced);
  std::printf("smooth mode capture of the torus at level 2: closed %d, %zu boundary edges, %zu unbalanced\n", int(st.closed),
              st.boundaryEdges, unbalanced);
  expectBadInput("render " + model + " --limit-only -o " + png, "--limit-only goes with --smooth");
  expectBadInput("render " + model + " --camera 1,2 -o " + png, "--camera 1,2: expected EX,EY,EZ,TX,TY,TZ,FOV");
  expectBadInput("render " + model + " --scene grid:3x4 -o " + png, "expected grid:NxN");
  expectBadInput("render " + model + " " + model + " -o " + png, "several models are drawn only in a --scene");
  expectBadInput("render " + model + " -o " + (dir / "t.jpg").string(), "-o writes a .png");
  expectBadInput("render " + model + " --cpu-level 9 -o " + png, "--cpu-level must lie between 0 and 6");
  expectBadInput("render " + model + " --size 0,10 -o " + png, "--size 0,10");
  expectBadInput("render " + (dir / "none.isoatlas").string() + " -o " + png, "cannot open");
}

// The demo's seeds and parameters go with Colin27's T1 however its path is written (here absolute,
// with a ./ inside), and with no other volume of that name.
TEST(Cli, EditAppliesBrushesOnBothBackendsAsADenseReferenceSays) {
  const auto dir = test::scratchDir();
  Volume mask = Volume::zeros({40, 36, 30}, ScalarType::UInt8);
  mask.spacing = {1, 1, 1.2};
  mask.origin = {-18, -20, -15};
  for (std::int64_t k = 0; k < 30; ++k)
    for (std::int64_t j = 0; j < 36; ++j)
      for (std::int64_t i = 0; i < 40; ++i)
        if (norm(mask.indexToWorld({double(i), double(j), double(k)}) - Vec3{0, 0, 2}) < 10) mask.setValue(mask.index(i, j, k), 1);
  const std::string input = (dir / "mask.nii.gz").string();
  writeVolume(input, mask);
  const std::string edits = " --union sphere:9,0,2,6 --subtract box:-20,-20,-20,-2,20,20 --union capsule:-12,-12,0,-12,12,0,2.5";
  auto expected = [&](const Vec3& p) {
    const bool box = p.x > -20 && p.x < -2 && p.y > -20 && p.y < 20 && p.z > -20 && p.z < 20;
    const Vec3 a{-12, -12, 0};
    const double t = std::clamp((p.y + 12) / 24, 0.0, 1.0);
    const bool capsule = norm(p - (a + Vec3{0, 24 * t, 0})) < 2.5;
    return ((norm(p - Vec3{0, 0, 2}) < 10 || norm(p - Vec3{9, 0, 2}) < 6) && !box) || capsule;
  };
  std::vector<std::byte> cpuVoxels;
  for (const char* backend : {"cpu", "gpu"}) {
    const std::string out = (dir / (std::string(backend) + ".nii.gz")).string(), report = (dir / "e.json").string();
    const Result r = run("edit " + input + edits + " --backend " + backend + " -o " + out + " --report " + report);
    ASSERT_EQ(r.code, 0) << r.err;
    const Volume edited = readVolume(out);
    EXPECT_EQ(edited.dims, mask.dims);
    EXPECT_EQ(edited.origin, mask.origin);
    std::int64_t wrong = 0, inside = 0;
    for (std::int64_t k = 0; k < 30; ++k)
      for (std::int64_t j = 0; j < 36; ++j)
        for (std::int64_t i = 0; i < 40; ++i) {
          const bool in = edited.at(i, j, k) == 1;
          inside += in;
          wrong += in != expected(mask.indexToWorld({double(i), double(j), double(k)}));
        }
    EXPECT_EQ(wrong, 0) << backend;
    EXPECT_GT(inside, 1000);
    if (cpuVoxels.empty()) cpuVoxels = edited.data;
    EXPECT_TRUE(edited.data == cpuVoxels) << "the backends disagree";
    const auto j = nlohmann::json::parse(test::readBytes(report));
    for (const char* key : {"nodes", "leaves", "depth_max", "seconds_write", "seconds_collapse", "bytes", "backend"})
      EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["backend"], backend);
    EXPECT_EQ(j["depth"], 18) << "the default depth is the input's voxels (64 = 2^6 a side)";
    EXPECT_EQ(j["collapses"], 1) << "once, at the end";
  }
  // A saved tree edits on, and comes back as the same voxels.
  const std::string tree = (dir / "t.dvt").string(), back = (dir / "back.nii.gz").string();
  ASSERT_EQ(run("edit " + input + edits + " -o " + tree).code, 0);
  const std::string picture = (dir / "tree.png").string();
  ASSERT_EQ(run("edit " + tree + " -o " + back + " --render " + picture + " --render-mode cubes --size 120,90").code, 0);
  EXPECT_EQ(readPng(picture).width, 120);
  const Volume again = readVolume(back);
  ASSERT_EQ(again.dims, mask.dims) << "a saved tree keeps its source's grid";
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(again.spacing[a], mask.spacing[a], 1e-6);
  for (std::int64_t k = 0; k < 30; ++k)
    for (std::int64_t j = 0; j < 36; ++j)
      for (std::int64_t i = 0; i < 40; ++i) ASSERT_EQ(again.at(i, j, k), double(std::to_integer<int>(cpuVoxels[mask.index(i, j, k)])));
  const Result info = run("info " + tree + " --report " + (dir / "i.json").string());
  ASSERT_EQ(info.code, 0) << info.err;
  const auto ij = nlohmann::json::parse(test::readBytes(dir / "i.json"));
  EXPECT_EQ(ij["kind"], "volume tree");
  EXPECT_GT(ij["inside_leaves"].get<int>(), 0);
  EXPECT_EQ(ij["voxel_depth"], 18);
  EXPECT_EQ(ij["mask_dims"], nlohmann::json({40, 36, 30}));
  // Collapsing after every write changes the tree's history, not its voxels; its time is counted.
  const std::string everyWrite = (dir / "every.nii.gz").string(), everyReport = (dir / "every.json").string();
  ASSERT_EQ(run("edit " + input + edits + " --collapse-every 1 -o " + everyWrite + " --report " + everyReport).code, 0);
  EXPECT_TRUE(readVolume(everyWrite).data == cpuVoxels);
  const auto every = nlohmann::json::parse(test::readBytes(everyReport));
  EXPECT_EQ(every["collapses"], 5) << "after the conversion and each of the 3 shapes, and at the end";
  EXPECT_GT(every["seconds_collapse"].get<double>(), 0);

  // A closed mesh as a shape: a box's 12 triangles, inside where a voxel's centre is, on both backends.
  const Vec3 lo{3.3, -8.6, -4.1}, hi{14.7, 6.4, 7.9};
  Mesh boxMesh;
  for (int c = 0; c < 8; ++c) boxMesh.positions.push_back({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
  for (const auto& q : std::vector<std::array<std::uint32_t, 4>>{{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}})
    boxMesh.addFace({q[0], q[1], q[2]}), boxMesh.addFace({q[0], q[2], q[3]});
  const std::string boxFile = (dir / "box.off").string();
  writeMesh(boxFile, boxMesh);
  std::vector<std::byte> meshStepVoxels;
  for (const char* backend : {"cpu", "gpu"}) {
    const std::string out = (dir / (std::string("mesh_step_") + backend + ".nii.gz")).string();
    const Result r = run("edit " + input + " --union mesh:" + boxFile + " --backend " + backend + " -o " + out);
    ASSERT_EQ(r.code, 0) << r.err;
    const Volume edited = readVolume(out);
    std::int64_t wrong = 0;
    for (std::int64_t k = 0; k < 30; ++k)
      for (std::int64_t j = 0; j < 36; ++j)
        for (std::int64_t i = 0; i < 40; ++i) {
          const Vec3 p = mask.indexToWorld({double(i), double(j), double(k)});
          const bool inBox = p.x > lo.x && p.x < hi.x && p.y > lo.y && p.y < hi.y && p.z > lo.z && p.z < hi.z;
          wrong += (edited.at(i, j, k) == 1) != (mask.at(i, j, k) == 1 || inBox);
        }
    EXPECT_EQ(wrong, 0) << backend;
    if (meshStepVoxels.empty()) meshStepVoxels = edited.data;
    EXPECT_TRUE(edited.data == meshStepVoxels) << "the backends disagree on a mesh step";
  }

  // A mesh out, and a closed mesh in (the same tree on both backends).
  const std::string surface = (dir / "edited.ply").string(), torus = (dir / "torus.off").string();
  ASSERT_EQ(run("edit " + tree + " -o " + surface).code, 0);
  const MeshTopology t = analyzeTopology(readMesh(surface));
  EXPECT_TRUE(t.closed && t.manifold);
  writeMesh(torus, test::torusMesh(40, 20));
  ASSERT_EQ(run("edit " + torus + " --depth 18 --subtract box:-5,-5,-5,0,5,5 -o " + surface).code, 0);
  const MeshTopology cut = analyzeTopology(readMesh(surface));
  EXPECT_TRUE(cut.closed && cut.manifold);
  EXPECT_EQ(cut.genus, 0) << "half a torus";
  for (const char* backend : {"cpu", "gpu"})
    ASSERT_EQ(run("edit " + torus + " --depth 18 --subtract box:-5,-5,-5,0,5,5 --backend " + backend + " -o " +
                  (dir / (std::string("torus_") + backend + ".dvt")).string()).code, 0);
  EXPECT_EQ(test::readBytes(dir / "torus_cpu.dvt"), test::readBytes(dir / "torus_gpu.dvt")) << "the backends' trees differ";

  expectBadInput("edit " + input + " --union sphere:1,2,3 -o " + back, "sphere takes 4 numbers");
  expectBadInput("edit " + input + " --subtract cube:1,2,3,4 -o " + back, "a shape is sphere:");
  expectBadInput("edit " + input + " --depth 60 --union sphere:1,2,3,4 -o " + back, "--depth: '60' is not in [1, 48]");
  expectBadInput("edit " + input + " --union sphere:1,2,3,4 -o x.png", "write a mask");
  // Depths whose voxels no memory holds: refused before any work, naming what to change.
  expectBadInput("edit " + torus + " --depth 45 -o " + surface, "choose a smaller --depth");
  expectBadInput("edit " + torus + " --depth 45 -o " + tree, "choose a smaller depth or a larger node limit");
  expectBadInput("edit " + input + " -o " + back + " --render t.png --render-mode splat", "--render-mode");
  expectBadInput("edit " + input + " --union mesh:" + (dir / "none.off").string() + " -o " + back, "none.off");
  test::writeBytes(dir / "bad.dvt", "ISOA-DVT\x01");
  expectBadInput("edit " + (dir / "bad.dvt").string() + " -o " + back, "bad.dvt");
  std::string damaged = test::readBytes(tree);
  damaged[damaged.size() - 5] ^= 0x40;
  test::writeBytes(dir / "damaged.dvt", damaged);
  expectBadInput("edit " + (dir / "damaged.dvt").string() + " -o " + back, "checksum");
}

TEST(Cli, RunKnowsTheDemoVolumeByItsIdentity) {
  const std::string ch2 = std::string(ISOATLAS_DATA) + "/./volumes/ch2.nii.gz";
  if (!std::filesystem::exists(ch2)) GTEST_SKIP() << "run scripts/fetch-data for the end-to-end data";
  const auto dir = test::scratchDir();
  const Result r = run("run " + ch2 + " --iterations 3 --backend cpu --levels 0 --samples 2000 -o " + (dir / "demo").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto report = nlohmann::json::parse(test::readBytes(dir / "demo/report.json"));
  EXPECT_EQ(report["segment"]["target"], 112);
  EXPECT_EQ(report["segment"]["width"], 14);
  EXPECT_EQ(report["segment"]["iterations"], 3);
  // Another volume named ch2.nii.gz gets no segmentation without seeds.
  writeVolume((dir / "ch2.nii.gz").string(), test::rampVolume(ScalarType::UInt8, {24, 20, 16}));
  const Result other = run("run " + (dir / "ch2.nii.gz").string() + " --backend cpu -o " + (dir / "other").string());
  ASSERT_EQ(other.code, 0) << other.err;
  EXPECT_FALSE(nlohmann::json::parse(test::readBytes(dir / "other/report.json")).contains("segment"));
}

TEST(Cli, Ch2IsReadWithItsTrueDimensions) {
  const std::string ch2 = std::string(ISOATLAS_DATA) + "/volumes/ch2.nii.gz";
  if (!std::filesystem::exists(ch2)) GTEST_SKIP() << "run scripts/fetch-data for the end-to-end data";
  const Result r = run("info " + ch2);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("181 x 217 x 181, uint8"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace isoatlas

namespace isoatlas {
namespace {

// render on a volume and its segmentation draws the window's views headless: the slices with the
// contour on the ball's outline, the volume rendering cut by a plane (the contour on its face), and
// the segmentation's volume tree.
TEST(Cli, RenderDrawsAVolumeAndItsSegmentationAsTheWindowDoes) {
  const auto dir = test::scratchDir();
  Volume v = Volume::zeros({40, 40, 40}, ScalarType::UInt8), mask = Volume::zeros({40, 40, 40}, ScalarType::UInt8);
  for (std::int64_t k = 0; k < 40; ++k)
    for (std::int64_t j = 0; j < 40; ++j)
      for (std::int64_t i = 0; i < 40; ++i) {
        const bool in = std::hypot(double(i) - 19.5, double(j) - 19.5, double(k) - 19.5) < 10;
        v.setValue(v.index(i, j, k), in ? 200 : 40 + i);
        mask.setValue(mask.index(i, j, k), in);
      }
  const std::string volume = (dir / "v.nii.gz").string(), seg = (dir / "m.nii.gz").string();
  writeVolume(volume, v);
  writeVolume(seg, mask);
  auto isContour = [](const std::uint8_t* c) { return c[0] == 255 && c[1] > 200 && c[1] < 240 && c[2] == 0; };

  const std::string slices = (dir / "s.png").string();
  ASSERT_EQ(run("render " + volume + " --segmentation " + seg + " --size 300,100 -o " + slices).code, 0);
  const Image s = readPng(slices);
  ASSERT_EQ(s.width, 300);
  ASSERT_EQ(s.height, 100);
  // Each panel: 40 mm over 100 pixels, the ball's 10 mm outline 25 pixels from the panel's centre.
  std::int64_t contour = 0, off = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 300; ++x)
      if (isContour(s.at(x, y))) ++contour, off += std::abs(std::hypot(x % 100 + 0.5 - 50, y + 0.5 - 50) - 25) > 2.5;
  EXPECT_GT(contour, 3 * 100);
  EXPECT_EQ(off, 0);

  const std::string cut = (dir / "v.png").string();
  ASSERT_EQ(run("render " + volume + " --segmentation " + seg + " --view volume --clip +y --size 160,160 -o " + cut).code, 0);
  const Image c = readPng(cut);
  std::int64_t face = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) face += isContour(c.at(x, y));
  EXPECT_GT(face, 30) << "the contour on the cut face (a ring of about 60 pixels)";

  // A tree of the segmentation, as the window's tree view draws it: the ball in the middle.
  const std::string tree = (dir / "t.dvt").string(), treePng = (dir / "t.png").string();
  ASSERT_EQ(run("edit " + seg + " -o " + tree).code, 0);
  for (const char* mode : {"raycast", "cubes"}) {
    ASSERT_EQ(run("render " + tree + " --view " + std::string(mode) + " --size 120,120 -o " + treePng).code, 0) << mode;
    const Image t = readPng(treePng);
    std::int64_t drawn = 0;
    for (int y = 40; y < 80; ++y)
      for (int x = 40; x < 80; ++x) drawn += t.at(x, y)[0] < 250 || t.at(x, y)[2] < 250;
    EXPECT_EQ(drawn, 40 * 40) << mode << ": the ball fills the middle";
  }
  expectBadInput("render " + tree + " --view slices -o x.png", "--view slices");

  expectBadInput("render " + volume + " --view cubes -o x.png", "--view cubes");
  expectBadInput("render " + volume + " --view volume --clip y -o x.png", "--clip y");
  expectBadInput("render " + volume + " --at 500,0,0 -o x.png", "--at");
  writeVolume((dir / "small.nii.gz").string(), Volume::zeros({8, 8, 8}, ScalarType::UInt8));
  expectBadInput("render " + volume + " --segmentation " + (dir / "small.nii.gz").string() + " -o x.png", "voxel grid");
}

}  // namespace
}  // namespace isoatlas

// isoatlas info FILE | --gl: what a volume, mesh or volume-tree file holds, or what the GL driver offers.
#include <cstdio>

#include "app/command.h"
#include "app/options.h"
#include "core/error.h"
#include "core/gl/context.h"
#include "core/mesh_io.h"
#include "core/mesh_topology.h"
#include "core/gz_file.h"
#include "core/volume_io.h"
#include "edit/dvt/dvt_file.h"

namespace isoatlas::app {
namespace {

nlohmann::json vec(const Vec3& v) { return {v.x, v.y, v.z}; }

int volumeInfo(const std::string& path, const VolumeReadOptions& read, nlohmann::json& r) {
  const Volume v = readVolume(path, read);
  const ValueRange range = valueRange(v);
  r["kind"] = "volume";
  r["file"] = path;
  r["dims"] = {v.dims[0], v.dims[1], v.dims[2]};
  r["spacing"] = vec(v.spacing);
  r["origin"] = vec(v.origin);
  r["direction"] = {vec(v.direction.column(0)), vec(v.direction.column(1)), vec(v.direction.column(2))};
  r["scalar_type"] = scalarTypeName(v.type);
  r["min"] = range.min;
  r["max"] = range.max;
  r["bytes"] = v.data.size();
  r["non_finite_voxels"] = v.nonFiniteVoxels;
  std::printf("%s: volume %lld x %lld x %lld, %s\n", path.c_str(), (long long)v.dims[0], (long long)v.dims[1],
              (long long)v.dims[2], scalarTypeName(v.type));
  std::printf("  spacing   %g x %g x %g mm\n", v.spacing.x, v.spacing.y, v.spacing.z);
  std::printf("  origin    (%g, %g, %g) mm (RAS)\n", v.origin.x, v.origin.y, v.origin.z);
  std::printf("  values    %g .. %g\n", range.min, range.max);
  if (v.nonFiniteVoxels > 0) std::printf("  %llu NaN or infinite voxels, read as the background (%g)\n", (unsigned long long)v.nonFiniteVoxels, range.min);
  return 0;
}

int meshInfo(const std::string& path, nlohmann::json& r) {
  const Mesh m = readMesh(path);
  const MeshTopology t = analyzeTopology(m);
  const Box box = boundingBox(m.positions);
  r["kind"] = "mesh";
  r["file"] = path;
  r["vertices"] = m.vertexCount();
  r["faces"] = m.faceCount();
  r["edges"] = t.edges;
  r["triangles_only"] = m.allFacesHave(3);
  r["closed"] = t.closed;
  r["manifold"] = t.manifold;
  r["oriented"] = t.oriented;
  r["components"] = t.components;
  r["boundary_loops"] = t.boundaryLoops;
  r["euler"] = t.euler;
  r["genus"] = t.manifold ? nlohmann::json(t.genus) : nlohmann::json(nullptr);
  r["bbox_min"] = vec(box.min);
  r["bbox_max"] = vec(box.max);
  std::printf("%s: mesh, %zu vertices, %zu faces%s\n", path.c_str(), m.vertexCount(), m.faceCount(),
              m.allFacesHave(3) ? " (triangles)" : (m.allFacesHave(4) ? " (quads)" : ""));
  std::printf("  closed %s, manifold %s, oriented %s, %zu component(s), %zu boundary loop(s)\n", t.closed ? "yes" : "no",
              t.manifold ? "yes" : "no", t.oriented ? "yes" : "no", t.components, t.boundaryLoops);
  if (t.manifold) std::printf("  euler %lld, genus %lld\n", t.euler, t.genus);
  std::printf("  bbox (%g, %g, %g) .. (%g, %g, %g)\n", box.min.x, box.min.y, box.min.z, box.max.x, box.max.y, box.max.z);
  // The figures are printed first, then the problem: every stage after info needs a 2-manifold.
  requireManifold(m, path);
  return 0;
}

int treeInfo(const std::string& path, nlohmann::json& r) {
  const edit::dvt::VolumeTree t = edit::dvt::readDvt(path);
  std::size_t inside = 0, band = 0;
  for (const auto& p : t.pointers)
    if (p.leaf()) inside += p.value == edit::dvt::kInside, band += p.value > edit::dvt::kOutside && p.value < edit::dvt::kInside;
  const std::int64_t n = t.frame.voxelsPerAxis();
  r["kind"] = "volume tree";
  r["file"] = path;
  r["nodes"] = t.nodeCount();
  r["leaves"] = t.leafCount();
  r["inside_leaves"] = inside;
  r["band_leaves"] = band;
  r["depth_max"] = t.maxDepth();
  r["voxel_depth"] = t.frame.voxelDepth();
  r["grid"] = {n, n, n};
  const auto mask = t.frame.grid();  // the source volume's voxels, which a mask of the tree comes back on
  r["mask_dims"] = {mask[0], mask[1], mask[2]};
  r["spacing"] = vec(t.frame.spacing);
  r["origin"] = vec(t.frame.origin);
  r["bytes"] = t.bytes();
  std::printf("%s: volume tree, %zu nodes, %zu leaves (%zu inside, %zu in the narrow band)\n", path.c_str(), t.nodeCount(),
              t.leafCount(), inside, band);
  std::printf("  depth up to %u (the grid's voxels at %u: %lld^3; a mask of it: %lld x %lld x %lld)\n", t.maxDepth(),
              t.frame.voxelDepth(), (long long)n, (long long)mask[0], (long long)mask[1], (long long)mask[2]);
  std::printf("  spacing   %g x %g x %g mm, origin (%g, %g, %g) mm\n", t.frame.spacing.x, t.frame.spacing.y, t.frame.spacing.z,
              t.frame.origin.x, t.frame.origin.y, t.frame.origin.z);
  return 0;
}

int glInfo(nlohmann::json& r) {
  auto ctx = gl::Context::headless();
  const gl::Info& i = ctx->info();
  r["kind"] = "gl";
  r["platform"] = i.platform;
  r["vendor"] = i.vendor;
  r["renderer"] = i.renderer;
  r["version"] = i.version;
  r["glsl"] = i.glsl;
  r["gl_version"] = std::to_string(i.major) + "." + std::to_string(i.minor);
  r["software"] = i.software();
  r["max_compute_work_group_size"] = {i.maxComputeWorkGroupSize[0], i.maxComputeWorkGroupSize[1],
                                      i.maxComputeWorkGroupSize[2]};
  r["max_compute_work_group_invocations"] = i.maxComputeWorkGroupInvocations;
  r["max_compute_shared_memory"] = i.maxComputeSharedMemory;
  r["max_texture_size"] = i.maxTextureSize;
  r["max_3d_texture_size"] = i.max3DTextureSize;
  r["max_tessellation_level"] = i.maxTessellationLevel;
  r["max_patch_vertices"] = i.maxPatchVertices;
  r["gl_contexts"] = gl::Context::made();
  std::printf("platform   %s\nvendor     %s\nrenderer   %s\nversion    %s (OpenGL %d.%d core)\nGLSL       %s\n",
              i.platform.c_str(), i.vendor.c_str(), i.renderer.c_str(), i.version.c_str(), i.major, i.minor,
              i.glsl.c_str());
  std::printf("max compute work group size    %d x %d x %d (%d invocations, %d bytes shared)\n",
              i.maxComputeWorkGroupSize[0], i.maxComputeWorkGroupSize[1], i.maxComputeWorkGroupSize[2],
              i.maxComputeWorkGroupInvocations, i.maxComputeSharedMemory);
  std::printf("max texture size               %d (3D %d)\nmax tessellation level         %d (patch vertices %d)\n",
              i.maxTextureSize, i.max3DTextureSize, i.maxTessellationLevel, i.maxPatchVertices);
  return 0;
}

}  // namespace

void addInfoCommand(CLI::App& app, int& exitCode) {
  auto* sub = app.add_subcommand("info", "what a volume, mesh or volume-tree file holds, or (--gl) what the GPU offers");
  auto file = std::make_shared<std::string>();
  auto gl = std::make_shared<bool>(false);
  sub->add_option("file", *file, "volume (.nii .nii.gz .nrrd .nhdr .inr .inr.gz, or a DICOM folder), mesh (.off .ply .obj .stl) or volume tree (.dvt)");
  sub->add_flag("--gl", *gl, "print the OpenGL renderer, version and the limits isoatlas relies on");
  auto read = std::make_shared<VolumeReadOptions>();
  addVolumeReadOptions(*sub, *read);
  bindAction(*sub, [file, gl, read](nlohmann::json& r) {
    if (*gl) return glInfo(r);
    require(!file->empty(), "give a FILE, or --gl");
    if (isVolumePath(*file)) return volumeInfo(*file, *read, r);
    if (isMeshPath(*file)) return meshInfo(*file, r);
    if (endsWith(*file, ".dvt")) return treeInfo(*file, r);
    throw Error(*file + ": unknown file type (volumes: .nii .nii.gz .nrrd .nhdr .inr .inr.gz or a DICOM folder; meshes: .off .ply .obj .stl; trees: .dvt)");
  }, exitCode);
}

}  // namespace isoatlas::app

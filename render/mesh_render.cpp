#include "render/mesh_render.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/gl/context.h"
#include "core/gl/program.h"
#include "core/gl/resources.h"
#include "core/polygon_triangulation.h"
#include "kRenderShaders.h"

namespace isoatlas::render {

namespace {

void requireSize(const MeshRenderOptions& o) {
  require(o.width > 0 && o.height > 0 && o.width <= 8192 && o.height <= 8192, "image size out of range");
}

// The triangles of `vao` (positions at attribute 0, normals at 1), `corners` indices, lit and framed on
// `box` (world), positions taken to the world by linear and offset, normals by normalToWorld.
Image drawMesh(const gl::VertexArray& vao, std::size_t corners, const Box& box, const Mat3& linear, const Vec3& offset,
               const Mat3& normalToWorld, const MeshRenderOptions& o) {
  gl::Context& ctx = gl::Context::current();
  // Orthographic camera around the bounding box.
  const Vec3 centre = (box.min + box.max) * 0.5;
  const double radius = std::max(box.diagonal() / 2, 1e-9);
  Vec3 forward = unit(o.viewDirection);
  Vec3 right = cross(forward, o.up);
  require(norm(right) > 1e-9, "view direction and up vector are parallel");
  right = unit(right);
  const Vec3 up = cross(right, forward);
  // Framed on the box's projection, with a 5 % margin.
  double extentR = 0, extentU = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner{(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y, (c & 4) ? box.max.z : box.min.z};
    extentR = std::max(extentR, std::fabs(dot(corner - centre, right)));
    extentU = std::max(extentU, std::fabs(dot(corner - centre, up)));
  }
  const double aspect = double(o.width) / o.height;
  const double halfW = std::max({extentR, extentU * aspect, 1e-9}) * 1.05;
  const double halfH = halfW / aspect;
  // Row-major rows of the matrix, uploaded transposed (GL is column-major), times toWorld's.
  // Depth grows along the view direction, so the nearest surface wins GL_LESS.
  const Vec3 rows[3] = {right * (1 / halfW), up * (1 / halfH), forward * (1 / radius)};
  float m[16] = {};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[c * 4 + r] = float(dot(rows[r], linear.column(c)));
    m[12 + r] = float(dot(rows[r], offset - centre));
  }
  m[15] = 1;
  float n[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) n[c * 3 + r] = float(normalToWorld.m[std::size_t(r)][std::size_t(c)]);

  gl::Framebuffer fbo(o.width, o.height);
  fbo.bind();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClearColor(float(o.background.x), float(o.background.y), float(o.background.z), 1);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const gl::Program& program = ctx.program({gl::kRenderShaders, {"render/shaders/mesh.vert", "render/shaders/mesh.frag"}, {}, {}});
  program.use();
  glUniformMatrix4fv(program.uniform("viewProjection"), 1, GL_FALSE, m);
  glUniformMatrix3fv(program.uniform("normalToWorld"), 1, GL_FALSE, n);
  glUniform3f(program.uniform("viewDirection"), float(forward.x), float(forward.y), float(forward.z));
  glUniform3f(program.uniform("colour"), float(o.colour.x), float(o.colour.y), float(o.colour.z));
  vao.bind();
  glDrawElements(GL_TRIANGLES, gl::glSize(corners, "drawing the mesh's corners"), GL_UNSIGNED_INT, nullptr);
  gl::checkErrors("drawing the mesh");

  return fbo.readImage();
}

// Position (vec3) at attribute 0 and normal (vec3) at 1, `stride` bytes a vertex, the normal
// `normalAt` bytes in.
void describeVertices(const gl::VertexArray& vao, unsigned vertices, unsigned indices, GLsizei stride, GLuint normalAt) {
  glVertexArrayVertexBuffer(vao.id(), 0, vertices, 0, stride);
  glVertexArrayElementBuffer(vao.id(), indices);
  for (GLuint a = 0; a < 2; ++a) {
    glEnableVertexArrayAttrib(vao.id(), a);
    glVertexArrayAttribFormat(vao.id(), a, 3, GL_FLOAT, GL_FALSE, a * normalAt);
    glVertexArrayAttribBinding(vao.id(), a, 0);
  }
}

}  // namespace

Image renderMesh(const Mesh& mesh, const MeshRenderOptions& o) {
  require(mesh.faceCount() > 0, "nothing to render: the mesh has no faces");
  requireSize(o);
  // Each vertex once (position and normal), the triangles as indices: a software renderer then
  // shades a shared vertex once, not once per corner.
  const std::vector<Vec3> normals = mesh.normals.size() == mesh.vertexCount() ? mesh.normals : vertexNormals(mesh);
  std::vector<float> vertices;
  vertices.reserve(mesh.vertexCount() * 6);
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const Vec3 &p = mesh.positions[v], &n = normals[v];
    vertices.insert(vertices.end(), {float(p.x), float(p.y), float(p.z), float(n.x), float(n.y), float(n.z)});
  }
  std::vector<std::uint32_t> corners;
  corners.reserve(mesh.faceCount() * 3);
  for (std::size_t f = 0; f < mesh.faceCount(); ++f) {
    const auto face = mesh.face(f);
    if (face.size() == 3) corners.insert(corners.end(), face.begin(), face.end());
    else
      for (const auto& t : triangulatePolygon(mesh.positions, face)) corners.insert(corners.end(), t.begin(), t.end());
  }
  const gl::Buffer buffer = gl::Buffer::of(vertices), indices = gl::Buffer::of(corners);
  gl::VertexArray vao;
  describeVertices(vao, buffer.id(), indices.id(), 6 * sizeof(float), 3 * sizeof(float));
  return drawMesh(vao, corners.size(), boundingBox(mesh.positions), Mat3{}, Vec3{}, Mat3{}, o);
}

Image renderMesh(const GpuMeshView& mesh, const MeshRenderOptions& o) {
  require(mesh.triangleCount > 0, "nothing to render: the mesh has no faces");
  requireSize(o);
  gl::VertexArray vao;
  describeVertices(vao, mesh.vertexBuffer, mesh.indexBuffer, 8 * sizeof(float), 4 * sizeof(float));
  return drawMesh(vao, std::size_t(mesh.triangleCount) * 3, mesh.box, mesh.linear, mesh.offset, mesh.normalToWorld, o);
}

void placeInVolume(GpuMeshView& view, const Volume& g, const Box& voxelBox) {
  const double scale[3] = {g.spacing.x, g.spacing.y, g.spacing.z};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      view.linear.m[std::size_t(r)][std::size_t(c)] = g.direction.m[std::size_t(r)][std::size_t(c)] * scale[c];
      view.normalToWorld.m[std::size_t(r)][std::size_t(c)] = g.direction.m[std::size_t(r)][std::size_t(c)] / scale[c];
    }
  view.offset = g.origin;
  std::vector<Vec3> corners;
  for (int c = 0; c < 8; ++c)
    corners.push_back(g.indexToWorld({(c & 1) ? voxelBox.max.x : voxelBox.min.x, (c & 2) ? voxelBox.max.y : voxelBox.min.y,
                                      (c & 4) ? voxelBox.max.z : voxelBox.min.z}));
  view.box = boundingBox(corners);
}

}  // namespace isoatlas::render

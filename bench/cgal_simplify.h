// The peer simplifier of bench/multires and bench/atlas: CGAL 5.5's edge collapse with
// Garland-Heckbert plane policies (optimal placement), stopped at an edge count.
#pragma once
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <chrono>

#include "core/mesh.h"

namespace isoatlas::bench {

using SurfaceMesh = CGAL::Surface_mesh<CGAL::Simple_cartesian<double>::Point_3>;

// CGAL 5.5 stops on an edge count: the base mesh's.
inline Mesh cgalSimplify(const Mesh& dense, std::size_t edges, double& seconds) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> v;
  for (const Vec3& p : dense.positions) v.push_back(sm.add_vertex({p.x, p.y, p.z}));
  for (std::size_t f = 0; f < dense.faceCount(); ++f) {
    const auto c = dense.face(f);
    sm.add_face(v[c[0]], v[c[1]], v[c[2]]);
  }
  const auto start = std::chrono::steady_clock::now();
  namespace SMS = CGAL::Surface_mesh_simplification;
  using Kernel = CGAL::Simple_cartesian<double>;
  SMS::Count_stop_predicate<SurfaceMesh> stop(edges);
  SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel> policies(sm);
  SMS::edge_collapse(sm, stop, CGAL::parameters::get_cost(policies.get_cost()).get_placement(policies.get_placement()));
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  sm.collect_garbage();
  Mesh out;
  for (const auto vi : sm.vertices()) {
    const auto& p = sm.point(vi);
    out.positions.push_back({p.x(), p.y(), p.z()});
  }
  for (const auto fi : sm.faces()) {
    std::vector<std::uint32_t> c;
    for (const auto vi : sm.vertices_around_face(sm.halfedge(fi))) c.push_back(std::uint32_t(vi.idx()));
    out.addFace(c);
  }
  return out;
}

}  // namespace isoatlas::bench

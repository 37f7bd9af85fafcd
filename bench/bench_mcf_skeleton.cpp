// Peer timing for bench/bench_skeleton.py: CGAL's mean curvature flow
// skeletonization (Tagliasacchi et al. 2012) on the same mesh, the tool a user
// would reach for instead of the Voronoi skeleton.
//
//   bench_mcf_skeleton mesh.off   ->   one line of JSON on stdout
#include "animanifold/io.hpp"

#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <vector>

using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using Skeletonization = CGAL::Mean_curvature_flow_skeletonization<Mesh>;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s mesh.(off|obj|ply|stl)\n", argv[0]);
    return 2;
  }
  try {
    const auto input = animanifold::read_mesh(argv[1]);
    Mesh mesh;
    std::vector<Mesh::Vertex_index> ids;
    for (Eigen::Index v = 0; v < input.vertices.rows(); ++v)
      ids.push_back(mesh.add_vertex(Kernel::Point_3(input.vertices(v, 0), input.vertices(v, 1), input.vertices(v, 2))));
    for (Eigen::Index f = 0; f < input.faces.rows(); ++f)
      if (mesh.add_face(ids[input.faces(f, 0)], ids[input.faces(f, 1)], ids[input.faces(f, 2)]) ==
          Mesh::null_face()) {
        std::fprintf(stderr, "bench_mcf_skeleton: face %ld could not be added (non-manifold input)\n",
                     static_cast<long>(f));
        return 2;
      }
    const auto start = std::chrono::steady_clock::now();
    Skeletonization::Skeleton skeleton;
    Skeletonization mcs(mesh);
    const auto contracted = std::chrono::steady_clock::now();
    mcs.contract_until_convergence();
    mcs.convert_to_skeleton(skeleton);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double setup = std::chrono::duration<double>(contracted - start).count();
    std::printf("{\"mcf_seconds\": %.6f, \"setup_seconds\": %.6f, \"vertices\": %ld, \"faces\": %ld, "
                "\"skeleton_vertices\": %zu, \"skeleton_edges\": %zu}\n",
                seconds, setup, static_cast<long>(input.vertices.rows()), static_cast<long>(input.faces.rows()),
                static_cast<size_t>(boost::num_vertices(skeleton)), static_cast<size_t>(boost::num_edges(skeleton)));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_mcf_skeleton: %s\n", e.what());
    return 2;
  }
  return 0;
}

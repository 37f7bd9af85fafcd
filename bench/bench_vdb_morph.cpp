// Peer for bench/bench_morph.py: OpenVDB's level-set morph between the same
// two closed meshes, the tool a user would reach for instead of a 4D fill.
//
//   bench_vdb_morph source.off target.off out_dir [voxels_per_diagonal=192]
//                   [tolerance_in_voxels=0.05] [max_time=400]
//
// Both meshes become narrow-band level sets on one grid (meshToLevelSet,
// voxel size = the target's bounding-box diagonal / voxels_per_diagonal),
// LevelSetMorphing advects the source toward the target until the interface
// is within `tolerance_in_voxels` of the target's, stops getting closer, or
// max_time is reached, and
// volumeToMesh extracts the frames at t = 0, mid (half the time taken) and 1,
// plus the target's own level set (the voxelisation alone, a floor for the
// end distance). Frames are written to out_dir as OFF (quads split); one line
// of JSON on stdout with the per-stage seconds and counts. VDB_MORPH_TRACE=1
// in the environment prints the front's distance after each unit of time.
//
// Not part of the normal build: bench_morph.py compiles it with g++, or
// configure with -DANIMANIFOLD_BUILD_VDB_BENCH=ON (needs libopenvdb-dev).
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetMorph.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

using openvdb::FloatGrid;
using openvdb::Vec3I;
using openvdb::Vec3s;
using openvdb::Vec4I;
using Clock = std::chrono::steady_clock;

struct Mesh {
  std::vector<Vec3s> points;
  std::vector<Vec3I> triangles;
};

// OFF with polygons (fan-triangulated); '#' comments skipped.
Mesh read_off(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::stringstream clean;
  for (std::string line; std::getline(in, line);) clean << line.substr(0, line.find('#')) << '\n';
  std::string header;
  clean >> header;
  if (header != "OFF") throw std::runtime_error(path + ": not an OFF file");
  long nv = 0, nf = 0, ne = 0;
  clean >> nv >> nf >> ne;
  Mesh mesh;
  for (long i = 0; i < nv; ++i) {
    double x, y, z;
    clean >> x >> y >> z;
    mesh.points.emplace_back(float(x), float(y), float(z));
  }
  for (long f = 0; f < nf; ++f) {
    int k;
    clean >> k;
    std::vector<unsigned> ids(k);
    for (auto& id : ids) clean >> id;
    for (int j = 1; j + 1 < k; ++j) mesh.triangles.emplace_back(ids[0], ids[j], ids[j + 1]);
  }
  if (!clean) throw std::runtime_error(path + ": truncated OFF file");
  return mesh;
}

void write_off(const std::string& path, const std::vector<Vec3s>& points, const std::vector<Vec3I>& triangles,
               const std::vector<Vec4I>& quads) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "OFF\n" << points.size() << ' ' << triangles.size() + 2 * quads.size() << " 0\n";
  out.precision(9);
  for (const auto& p : points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& t : triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  for (const auto& q : quads)
    out << "3 " << q[0] << ' ' << q[1] << ' ' << q[2] << "\n3 " << q[0] << ' ' << q[2] << ' ' << q[3] << '\n';
}

// Triangles of the zero iso-surface (adaptivity 0: no decimation).
size_t extract(const FloatGrid& grid, const std::string& path) {
  std::vector<Vec3s> points;
  std::vector<Vec3I> triangles;
  std::vector<Vec4I> quads;
  openvdb::tools::volumeToMesh(grid, points, triangles, quads, 0.0, 0.0);
  write_off(path, points, triangles, quads);
  return triangles.size() + 2 * quads.size();
}

// Largest |phi - phi_target| over the voxels at the interface (|phi| < dx/2):
// how far, in world units, the front still is from the target's.
double residual(const FloatGrid& phi, const FloatGrid& target, double dx) {
  auto acc = target.getConstAccessor();
  double worst = 0.0;
  for (auto it = phi.cbeginValueOn(); it; ++it) {
    const double v = *it;
    if (std::abs(v) >= 0.5 * dx) continue;
    worst = std::max(worst, std::abs(v - double(acc.getValue(it.getCoord()))));
  }
  return worst;
}

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr,
                 "usage: %s source.off target.off out_dir [voxels_per_diagonal=192] [tolerance_in_voxels=0.05] "
                 "[max_time=400]\n",
                 argv[0]);
    return 2;
  }
  try {
    openvdb::initialize();
    const std::string out_dir = argv[3];
    const double per_diagonal = argc > 4 ? std::atof(argv[4]) : 192.0;
    const double tolerance_voxels = argc > 5 ? std::atof(argv[5]) : 0.05;
    const double max_time = argc > 6 ? std::atof(argv[6]) : 400.0;
    const Mesh source = read_off(argv[1]), target = read_off(argv[2]);

    auto diagonal = [](const Mesh& m) {
      Vec3s lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
      for (const auto& p : m.points) lo = openvdb::math::minComponent(lo, p), hi = openvdb::math::maxComponent(hi, p);
      return double((hi - lo).length());
    };
    const double dx = diagonal(target) / per_diagonal;
    const float half_width = float(openvdb::LEVEL_SET_HALF_WIDTH);

    // Stage 1: both shapes as narrow-band level sets on one (aligned) grid.
    auto start = Clock::now();
    const auto xform = openvdb::math::Transform::createLinearTransform(dx);
    FloatGrid::Ptr phi = openvdb::tools::meshToLevelSet<FloatGrid>(*xform, source.points, source.triangles, half_width);
    FloatGrid::Ptr goal = openvdb::tools::meshToLevelSet<FloatGrid>(*xform, target.points, target.triangles, half_width);
    const double levelset_seconds = seconds_since(start);
    const FloatGrid::Ptr start_grid = phi->deepCopy();

    // Stage 2: advect toward the target in chunks of time, checking how far
    // the front still is. Copies of the grid at chunk ends that could still
    // be the middle frame (time >= now / 2) are kept.
    start = Clock::now();
    openvdb::tools::LevelSetMorphing<FloatGrid> morph(*phi, *goal);
    morph.setSpatialScheme(openvdb::math::HJWENO5_BIAS);
    morph.setTemporalScheme(openvdb::math::TVD_RK2);
    const double chunk = 1.0;
    double time = 0.0, left = residual(*phi, *goal, dx);
    size_t cfl_steps = 0;
    std::vector<std::pair<double, FloatGrid::Ptr>> kept{{0.0, start_grid}};
    bool converged = left <= tolerance_voxels * dx;
    while (!converged && time < max_time) {
      const double before = left;
      const size_t steps = morph.advect(float(time), float(time + chunk));
      cfl_steps += steps;
      time += chunk;
      left = residual(*phi, *goal, dx);
      // Done when close enough, or when the front no longer moves (the
      // residual stalls at a fraction of a voxel: the tracker's
      // renormalisation and the target's sampling disagree by that much).
      converged = left <= tolerance_voxels * dx || steps == 0 || (left < dx && left > 0.99 * before);
      if (std::getenv("VDB_MORPH_TRACE")) std::fprintf(stderr, "t=%g steps=%zu residual=%g voxels\n", time, steps, left / dx);
      kept.emplace_back(time, phi->deepCopy());
      while (kept.size() > 2 && kept[1].first < time / 2) kept.erase(kept.begin());
    }
    const double morph_seconds = seconds_since(start);
    auto mid = kept.front();
    for (const auto& k : kept)
      if (std::abs(k.first - time / 2) < std::abs(mid.first - time / 2)) mid = k;

    // Stage 3: the frames as meshes.
    start = Clock::now();
    const size_t f0 = extract(*start_grid, out_dir + "/vdb_t0.off");
    const size_t fm = extract(*mid.second, out_dir + "/vdb_mid.off");
    const size_t f1 = extract(*phi, out_dir + "/vdb_t1.off");
    const double mesh_seconds = seconds_since(start);
    extract(*goal, out_dir + "/vdb_target.off");

    std::printf(
        "{\"voxel_size\": %.9g, \"voxels_per_diagonal\": %.6g, \"levelset_seconds\": %.6f, \"morph_seconds\": %.6f, "
        "\"mesh_seconds\": %.6f, \"morph_time\": %.6g, \"mid_time\": %.6g, \"cfl_steps\": %zu, \"converged\": %s, "
        "\"residual_voxels\": %.6g, \"active_voxels\": %llu, \"faces_t0\": %zu, \"faces_mid\": %zu, "
        "\"faces_t1\": %zu, \"threads\": %d}\n",
        dx, per_diagonal, levelset_seconds, morph_seconds, mesh_seconds, time, mid.first, cfl_steps,
        converged ? "true" : "false", left / dx, static_cast<unsigned long long>(phi->activeVoxelCount()), f0, fm, f1,
        static_cast<int>(std::thread::hardware_concurrency()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_vdb_morph: %s\n", e.what());
    return 2;
  }
  return 0;
}

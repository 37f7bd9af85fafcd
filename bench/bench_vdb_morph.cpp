// Peer for bench/bench_morph.py: OpenVDB's level-set morph between the same
// two closed meshes, the tool a user would reach for instead of a 4D fill.
//
//   bench_vdb_morph source.off target.off out_dir [voxels_per_diagonal=192]
//                   [tolerance_in_voxels=0.05] [max_time=400] [frames=N]
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
// frames=N (a key=value argument anywhere after out_dir; default 0 = off)
// also writes N + 2 frames evenly spread over the morph's time T, frame k at
// k/(N+1) of T, as vdb_frame_000.off ... vdb_frame_{N+1}.off, and the frame at
// T/4 as vdb_quarter.off. T is only known once the front has converged, so
// the advection is run twice: the first pass (timed as morph_seconds) finds
// T; the second replays it from the start grid, stopping exactly at each
// frame's time (timed apart as replay_seconds, not part of the morph's cost).
// Frame 0 is the start grid and frame N+1 the first pass's final grid (the
// same grids as vdb_t0.off / vdb_t1.off). The replay stops at other times
// than the first pass's unit chunks, so its CFL steps differ slightly; the
// frames are the morph up to that rounding.
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

// The length of the mesh's bounding-box diagonal.
double diagonal(const Mesh& m) {
  Vec3s lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const auto& p : m.points) lo = openvdb::math::minComponent(lo, p), hi = openvdb::math::maxComponent(hi, p);
  return double((hi - lo).length());
}

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The morph's settings, the same in both passes.
void configure(openvdb::tools::LevelSetMorphing<FloatGrid>& morph) {
  morph.setSpatialScheme(openvdb::math::HJWENO5_BIAS);
  morph.setTemporalScheme(openvdb::math::TVD_RK2);
}

std::string frame_name(const std::string& out_dir, int k) {
  char name[32];
  std::snprintf(name, sizeof name, "/vdb_frame_%03d.off", k);
  return out_dir + name;
}

struct FrameTimings {
  std::vector<double> times;  // of vdb_frame_000 ... vdb_frame_{n+1}
  double quarter_time = 0.0;
  double replay_seconds = 0.0, mesh_seconds = 0.0;
};

// The second pass (see the top): n + 2 frames at k/(n+1) of `total` and the
// one at total/4, advecting a copy of `start` toward `goal` from stop to stop.
FrameTimings write_frames(const FloatGrid& start, const FloatGrid& goal, const FloatGrid& end, double total, int n,
                          const std::string& out_dir) {
  FrameTimings out;
  for (int k = 0; k <= n + 1; ++k) out.times.push_back(total * k / (n + 1));
  out.quarter_time = total / 4;
  std::vector<double> stops(out.times.begin() + 1, out.times.end() - 1);
  stops.push_back(out.quarter_time);
  std::sort(stops.begin(), stops.end());

  FloatGrid::Ptr phi = start.deepCopy();
  openvdb::tools::LevelSetMorphing<FloatGrid> morph(*phi, goal);
  configure(morph);
  double now = 0.0;
  for (double stop : stops) {
    auto clock = Clock::now();
    if (stop > now) morph.advect(float(now), float(stop));
    now = std::max(now, stop);
    out.replay_seconds += seconds_since(clock);
    clock = Clock::now();
    if (stop == out.quarter_time) extract(*phi, out_dir + "/vdb_quarter.off");
    for (int k = 1; k <= n; ++k)
      if (out.times[k] == stop) extract(*phi, frame_name(out_dir, k));
    out.mesh_seconds += seconds_since(clock);
  }
  const auto clock = Clock::now();
  extract(start, frame_name(out_dir, 0));
  extract(end, frame_name(out_dir, n + 1));
  out.mesh_seconds += seconds_since(clock);
  return out;
}

std::string json_list(const std::vector<double>& values) {
  std::string text = "[";
  char number[32];
  for (size_t i = 0; i < values.size(); ++i) {
    std::snprintf(number, sizeof number, "%s%.9g", i ? ", " : "", values[i]);
    text += number;
  }
  return text + "]";
}

// Stage 4's JSON fields (each after a comma).
std::string frames_fields(const FrameTimings& ft, int n) {
  char text[256];
  std::snprintf(text, sizeof text,
                ", \"frames\": %d, \"quarter_time\": %.9g, \"replay_seconds\": %.6f, \"frames_mesh_seconds\": %.6f, "
                "\"frame_times\": ",
                n, ft.quarter_time, ft.replay_seconds, ft.mesh_seconds);
  return text + json_list(ft.times);
}

struct Options {
  std::string source, target, out_dir;
  double per_diagonal = 192.0, tolerance_voxels = 0.05, max_time = 400.0;
  int frames = 0;
};

// The positional arguments, and frames=N anywhere after out_dir; false when
// they do not make a run.
bool parse_options(int argc, char** argv, Options& options) {
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (i > 3 && arg.rfind("frames=", 0) == 0)
      options.frames = std::atoi(arg.c_str() + 7);
    else
      positional.push_back(arg);
  }
  if (positional.size() < 3 || positional.size() > 6 || options.frames < 0) return false;
  options.source = positional[0], options.target = positional[1], options.out_dir = positional[2];
  if (positional.size() > 3) options.per_diagonal = std::atof(positional[3].c_str());
  if (positional.size() > 4) options.tolerance_voxels = std::atof(positional[4].c_str());
  if (positional.size() > 5) options.max_time = std::atof(positional[5].c_str());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse_options(argc, argv, options)) {
    std::fprintf(stderr,
                 "usage: %s source.off target.off out_dir [voxels_per_diagonal=192] [tolerance_in_voxels=0.05] "
                 "[max_time=400] [frames=N]\n",
                 argv[0]);
    return 2;
  }
  try {
    openvdb::initialize();
    const std::string& out_dir = options.out_dir;
    const double per_diagonal = options.per_diagonal, tolerance_voxels = options.tolerance_voxels;
    const double max_time = options.max_time;
    const Mesh source = read_off(options.source), target = read_off(options.target);

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
    configure(morph);
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

    // Stage 4 (frames=N only): the evenly spread frames, from a replay.
    const std::string frames_json =
        options.frames > 0
            ? frames_fields(write_frames(*start_grid, *goal, *phi, time, options.frames, out_dir), options.frames)
            : std::string();

    std::printf(
        "{\"voxel_size\": %.9g, \"voxels_per_diagonal\": %.6g, \"levelset_seconds\": %.6f, \"morph_seconds\": %.6f, "
        "\"mesh_seconds\": %.6f, \"morph_time\": %.6g, \"mid_time\": %.6g, \"cfl_steps\": %zu, \"converged\": %s, "
        "\"residual_voxels\": %.6g, \"active_voxels\": %llu, \"faces_t0\": %zu, \"faces_mid\": %zu, "
        "\"faces_t1\": %zu, \"threads\": %d%s}\n",
        dx, per_diagonal, levelset_seconds, morph_seconds, mesh_seconds, time, mid.first, cfl_steps,
        converged ? "true" : "false", left / dx, static_cast<unsigned long long>(phi->activeVoxelCount()), f0, fm, f1,
        static_cast<int>(std::thread::hardware_concurrency()), frames_json.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_vdb_morph: %s\n", e.what());
    return 2;
  }
  return 0;
}

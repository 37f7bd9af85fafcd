#include "animanifold/morph_validity.hpp"

#include "animanifold/self_intersection.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/threads.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace animanifold {

namespace {

// Evenly spread frames checked first.
constexpr int kSpreadFrames = 24;
// Rounds of bisection towards each change of topology between checked
// frames, and the most frames they may add in all.
constexpr int kBisections = 5;
constexpr int kBisectionFrames = 24;
// Crossings shallower than this share of the size are rounding (see
// self_intersection.hpp).
constexpr double kCrossingTolerance = 1e-9;

struct FrameTopology {
  Index euler = 0, pieces = 0, cavities = 0;
  double solid = 0, cavity = 0;  // volumes
  bool operator!=(const FrameTopology& o) const {
    return euler != o.euler || pieces != o.pieces || cavities != o.cavities;
  }
};

// Euler characteristic, outer shells (pieces) and cavities (shells whose
// signed volume is negative: their faces point into a bubble) of a closed
// triangle mesh.
FrameTopology topology_of(const PointMatrix& V, const SimplexMatrix& F) {
  FrameTopology out;
  if (F.rows() == 0) return out;
  std::vector<Index> parent(V.rows());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](Index a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  std::vector<std::pair<Index, Index>> edges;
  std::vector<bool> used(V.rows(), false);
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index a = F(f, k), b = F(f, (k + 1) % 3);
      used[a] = true;
      edges.emplace_back(std::min(a, b), std::max(a, b));
      parent[find(a)] = find(b);
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const Index vertices = static_cast<Index>(std::count(used.begin(), used.end(), true));
  out.euler = vertices - static_cast<Index>(edges.size()) + static_cast<Index>(F.rows());
  std::map<Index, double> volume;
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    volume[find(F(f, 0))] += a.dot(b.cross(c)) / 6.0;
  }
  for (const auto& [root, v] : volume) {
    (v < 0 ? out.cavities : out.pieces)++;
    (v < 0 ? out.cavity : out.solid) += std::abs(v);
  }
  return out;
}

}  // namespace

void check_frames(const Complex& manifold, double t0, double t1, const PointMatrix& VS, const SimplexMatrix& FS,
                  const PointMatrix& VT, const SimplexMatrix& FT, MorphReport& report,
                  const std::function<void()>& alongside) {
  const FrameTopology source = topology_of(VS, FS), target = topology_of(VT, FT);
  const Index least_euler = std::min(source.euler, target.euler), most_euler = std::max(source.euler, target.euler);
  const Index most_pieces = std::max(source.pieces, target.pieces);
  const Index most_cavities = std::max(source.cavities, target.cavities);
  const double size = std::max((VS.colwise().maxCoeff() - VS.colwise().minCoeff()).norm(),
                               (VT.colwise().maxCoeff() - VT.colwise().minCoeff()).norm());
  Slicer slicer(std::make_shared<const Complex>(manifold));
  const int axis = manifold.ambient_dimension() - 1;
  slicer.index(axis);  // built once here: the frames below only read it, from several threads
  struct Frame {
    FrameTopology topology;
    bool crossing = false;
  };
  auto examine = [&](double t, bool look_for_crossings) {
    Frame out;
    const Slice frame = slicer.slice(axis, t);
    out.topology = topology_of(frame.vertices, frame.faces);
    try {
      out.crossing =
          look_for_crossings && !self_intersections(frame.vertices, frame.faces, 1, kCrossingTolerance * size).empty();
    } catch (const std::exception&) {
      out.crossing = true;  // not even a closed manifold there
    }
    return out;
  };
  std::map<double, FrameTopology> checked;
  auto record = [&](double t, const Frame& frame) {
    const FrameTopology& topology = frame.topology;
    checked[t] = topology;
    ++report.frames_checked;
    if (topology.euler < least_euler || topology.euler > most_euler || topology.pieces > most_pieces)
      report.noise_frames.push_back(t);
    if (topology.cavities > most_cavities) {
      report.bubble_frames.emplace_back(t, topology.cavities - most_cavities);
      report.largest_bubble_fraction =
          std::max(report.largest_bubble_fraction, topology.cavity / std::max(topology.solid, 1e-300));
    }
    if (frame.crossing) report.crossing_frames.push_back(t);
  };
  // Frames are independent: examined on all cores, each into its own slot,
  // recorded in time order.
  // `work`, when given, is one more item of the loop, taken first.
  auto check_all = [&](const std::vector<double>& times, bool look_for_crossings, const std::function<void()>& work) {
    std::vector<Frame> frames(times.size());
    std::exception_ptr failure;  // only the work's item writes it
    const long first = work ? -1 : 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
    for (long i = first; i < static_cast<long>(times.size()); ++i) {
      if (i >= 0) {
        frames[i] = examine(times[i], look_for_crossings);
        continue;
      }
      try {
        work();
      } catch (...) {
        failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
    for (size_t i = 0; i < times.size(); ++i) record(times[i], frames[i]);
  };
  // Coarse to fine (the middle, the quarters, ...), so the costly frames
  // come first to the cores.
  std::vector<int> order(kSpreadFrames);
  std::iota(order.begin(), order.end(), 1);
  auto coarseness = [](int i) { return i == 0 ? 32 : __builtin_ctz(static_cast<unsigned>(i)); };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return coarseness(a) > coarseness(b); });
  std::vector<double> spread;
  for (const int i : order) spread.push_back(t0 + (t1 - t0) * i / (kSpreadFrames + 1));
  check_all(spread, true, alongside);
  // Towards every change of topology between neighbouring checked frames,
  // in time order, up to kBisectionFrames in all.
  int bisection_frames = 0;
  for (int round = 0; round < kBisections && !report.frames_capped; ++round) {
    std::vector<double> middles;
    for (auto it = checked.begin(); std::next(it) != checked.end(); ++it)
      if (it->second != std::next(it)->second) middles.push_back(0.5 * (it->first + std::next(it)->first));
    if (middles.empty()) break;
    if (bisection_frames + static_cast<int>(middles.size()) > kBisectionFrames) {
      middles.resize(static_cast<size_t>(kBisectionFrames - bisection_frames));
      report.frames_capped = true;
    }
    bisection_frames += static_cast<int>(middles.size());
    check_all(middles, false, {});
  }
  for (auto it = checked.begin(); it != checked.end() && std::next(it) != checked.end(); ++it)
    if (it->second != std::next(it)->second) ++report.topology_changes;
  for (auto* times : {&report.noise_frames, &report.crossing_frames}) std::sort(times->begin(), times->end());
  std::sort(report.bubble_frames.begin(), report.bubble_frames.end());
}

}  // namespace animanifold

#include "animanifold/morph_validity.hpp"

#include "animanifold/self_intersection.hpp"
#include "animanifold/slice.hpp"
#include "animanifold/threads.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <cstdlib>
#include <numeric>
#include <stdexcept>

namespace animanifold {

namespace {

// Evenly spread frames checked first.
constexpr int kSpreadFrames = 24;
// Levels of bisection towards each change of topology between checked
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

// The number of distinct values among `other[0..count)`, the larger ends
// of one vertex's edges: a handful, where a pairwise count beats a sort's
// setup; more (a fan's hub) are sorted.
Index distinct_among(Index* other, Index count) {
  constexpr Index kPairwise = 16;
  if (count > kPairwise) {
    std::sort(other, other + count);
    return static_cast<Index>(std::unique(other, other + count) - other);
  }
  Index distinct = 0;
  for (Index i = 0; i < count; ++i) {
    bool earlier = false;
    for (Index j = 0; j < i && !earlier; ++j) earlier = other[j] == other[i];
    distinct += !earlier;
  }
  return distinct;
}

// Euler characteristic, outer shells (pieces) and cavities (shells whose
// signed volume is negative: their faces point into a bubble) of a closed
// triangle mesh. One pass over the faces joins each face's corners (union-
// find) and counts its edges at their smaller end; a second lists each
// edge's larger end there (a counting sort), where a vertex's few edges are
// told apart; a third sums each shell's signed volume.
FrameTopology topology_of(const PointMatrix& V, const SimplexMatrix& F) {
  FrameTopology out;
  if (F.rows() == 0) return out;
  const Index n = static_cast<Index>(V.rows());
  std::vector<Index> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](Index a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  // The larger root goes under the smaller: every root is its shell's
  // least vertex, and the trees stay shallow where the faces, in the order
  // the slicer met them, would otherwise chain long paths.
  auto join = [&](Index a, Index b) {
    a = find(a), b = find(b);
    if (a < b) parent[b] = a;
    else parent[a] = b;
  };
  std::vector<Index> start(static_cast<size_t>(n) + 1, 0);
  std::vector<char> used(n, 0);
  for (Index f = 0; f < F.rows(); ++f) {
    const Index a = F(f, 0), b = F(f, 1), c = F(f, 2);
    used[a] = used[b] = used[c] = 1;
    join(a, b);  // two unions join all three corners
    join(b, c);
    ++start[std::min(a, b) + 1], ++start[std::min(b, c) + 1], ++start[std::min(c, a) + 1];
  }
  for (Index v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<Index> other(static_cast<size_t>(start.back()));
  {
    std::vector<Index> next(start.begin(), start.end() - 1);
    for (Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const Index a = F(f, k), b = F(f, (k + 1) % 3);
        other[next[std::min(a, b)]++] = std::max(a, b);
      }
  }
  Index vertices = 0, edges = 0;
  for (Index v = 0; v < n; ++v) {
    vertices += used[v];
    edges += distinct_among(other.data() + start[v], start[v + 1] - start[v]);
    parent[v] = find(v);  // every vertex straight to its root, for the volumes' pass
  }
  out.euler = vertices - edges + static_cast<Index>(F.rows());
  std::vector<double> volume(n, 0.0);
  std::vector<char> shell(n, 0);
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Index root = parent[F(f, 0)];
    volume[root] += a.dot(b.cross(c)) / 6.0;
    shell[root] = 1;
  }
  for (Index root = 0; root < n; ++root) {
    if (!shell[root]) continue;
    const double v = volume[root];
    (v < 0 ? out.cavities : out.pieces)++;
    (v < 0 ? out.cavity : out.solid) += std::abs(v);
  }
  return out;
}

// The checks of one manifold's frames (check_frames).
class FrameChecks {
 public:
  FrameChecks(const Complex& manifold, const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT,
              const SimplexMatrix& FT, MorphReport& report)
      // The slicer reads the manifold where it is (an aliasing pointer that
      // owns nothing): check_frames() ends before its caller's manifold does.
      : report_(report), slicer_(std::shared_ptr<const Complex>(std::shared_ptr<const Complex>(), &manifold)),
        axis_(manifold.ambient_dimension() - 1) {
    const FrameTopology source = topology_of(VS, FS), target = topology_of(VT, FT);
    least_euler_ = std::min(source.euler, target.euler), most_euler_ = std::max(source.euler, target.euler);
    most_pieces_ = std::max(source.pieces, target.pieces);
    most_cavities_ = std::max(source.cavities, target.cavities);
    tolerance_ = kCrossingTolerance * std::max((VS.colwise().maxCoeff() - VS.colwise().minCoeff()).norm(),
                                               (VT.colwise().maxCoeff() - VT.colwise().minCoeff()).norm());
  }

  // Builds the slicer's index once (the first frame's work, or an item of
  // the first loop of check()); a thread that asks meanwhile waits for it.
  // After that the frames only read it, from several threads.
  void index() {
    std::call_once(indexed_, [this] { slicer_.index(axis_); });
  }

  // Examines the frames at `times` on all cores, each into its own slot,
  // and records them in time order; the first `crossing_count` are checked
  // for crossings too. The `alongside` work items are more items of the
  // loop, taken first, after the slicer's index (so that one core builds it
  // while the other starts on them); what one throws is thrown once the
  // frames are done.
  void check(const std::vector<double>& times, long crossing_count,
             const std::vector<std::function<void()>>& alongside = {}) {
    std::vector<Frame> frames(times.size());
    std::vector<std::function<void()>> items{[this] { index(); }};
    items.insert(items.end(), alongside.begin(), alongside.end());
    // Each item and frame writes its own slot; nothing thrown may leave the
    // parallel loop (the index, built by an item, can throw in a frame too).
    std::vector<std::exception_ptr> failure(items.size() + times.size());
    const long first = -static_cast<long>(items.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
    for (long i = first; i < static_cast<long>(times.size()); ++i) {
      try {
        if (i >= 0) frames[i] = examine(times[i], i < crossing_count);
        else items[static_cast<size_t>(i - first)]();
      } catch (...) {
        failure[static_cast<size_t>(i - first)] = std::current_exception();
      }
    }
    for (const std::exception_ptr& e : failure)
      if (e) std::rethrow_exception(e);
    for (size_t i = 0; i < times.size(); ++i) record(times[i], frames[i]);
    report_.crossing_frames_checked += std::min(crossing_count, static_cast<long>(times.size()));
  }

  // Checks the frames at `times`, already examined, for crossings only.
  void check_crossings(const std::vector<double>& times) {
    std::vector<char> crossing(times.size(), 0);
    std::vector<std::exception_ptr> failure(times.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(thread_count())
    for (long i = 0; i < static_cast<long>(times.size()); ++i) {
      try {
        crossing[i] = crosses(slicer_.slice_shape(axis_, times[i]));
      } catch (...) {
        failure[i] = std::current_exception();
      }
    }
    for (const std::exception_ptr& e : failure)
      if (e) std::rethrow_exception(e);
    for (size_t i = 0; i < times.size(); ++i)
      if (crossing[i]) report_.crossing_frames.push_back(times[i]);
    report_.crossing_frames_checked += static_cast<Index>(times.size());
  }

  // Towards every change of topology between neighbouring checked frames.
  // Each such pair of frames is bisected on its own, level by level: up to
  // kBisections levels, and first its share of kBisectionFrames frames (the
  // same for every pair, the earlier pairs taking what does not divide).
  // The pairs are independent, so their frames are tasks on all cores and
  // no pair waits for another's level. Then what the pairs left of the
  // frames goes to the pairs still holding changes, in time order. What
  // each finds depends only on the manifold, never on the threads.
  void bisect_changes() {
    std::vector<Bisection> bisections;
    for (auto it = checked_.begin(); std::next(it) != checked_.end(); ++it)
      if (it->second != std::next(it)->second) bisections.emplace_back().pending.push_back({{*it, *std::next(it)}, 0});
    const int pairs = static_cast<int>(bisections.size());
    std::vector<int> spent(bisections.size(), 0);
    std::exception_ptr failure;  // nothing thrown may leave a task or the parallel region
#pragma omp parallel num_threads(thread_count())
#pragma omp single
    {
#pragma omp taskgroup
      for (int p = 0; p < pairs; ++p) {
        const int share = kBisectionFrames / pairs + (p < kBisectionFrames % pairs ? 1 : 0);
#pragma omp task firstprivate(p, share) shared(bisections, spent)
        try {
          spent[p] = bisect(bisections[p], share);
        } catch (...) {
          bisections[p].failure = std::current_exception();
        }
      }
      try {
        int left = kBisectionFrames - std::accumulate(spent.begin(), spent.end(), 0);
        for (Bisection& b : bisections)
          if (left > 0 && !b.failure) left -= bisect(b, left);
      } catch (...) {
        failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
    for (const Bisection& b : bisections)
      if (b.failure) std::rethrow_exception(b.failure);
    for (const Bisection& b : bisections) {
      for (const auto& [t, frame] : b.frames) record(t, frame);
      report_.frames_capped = report_.frames_capped || !b.pending.empty();
    }
  }

  // Counts the changes of topology and puts the report's lists in time order.
  void finish() {
    for (auto it = checked_.begin(); it != checked_.end() && std::next(it) != checked_.end(); ++it)
      if (it->second != std::next(it)->second) ++report_.topology_changes;
    for (auto* times : {&report_.noise_frames, &report_.crossing_frames}) std::sort(times->begin(), times->end());
    std::sort(report_.bubble_frames.begin(), report_.bubble_frames.end());
  }

 private:
  struct Frame {
    FrameTopology topology;
    bool crossing = false;
  };
  // Two checked frames whose topology differs: (time, topology) at each end.
  using Span = std::pair<std::pair<double, FrameTopology>, std::pair<double, FrameTopology>>;
  // The bisection of one change: the spans still holding a change, each
  // with its level (0 for the change itself), in order of level then time;
  // the frames examined; what examining one threw.
  struct Bisection {
    std::deque<std::pair<Span, int>> pending;
    std::vector<std::pair<double, Frame>> frames;
    std::exception_ptr failure;
  };

  // Examines the middles of up to `budget` of b's pending spans, a level at
  // a time (each level's frames are tasks; the earlier spans of a level
  // first), and queues the halves that still hold a change, below
  // kBisections levels. Returns how many frames it examined.
  int bisect(Bisection& b, int budget) {
    int spent = 0;
    while (!b.pending.empty() && spent < budget && !b.failure) {
      const int level = b.pending.front().second;
      std::vector<Span> spans;
      while (!b.pending.empty() && b.pending.front().second == level && spent < budget) {
        spans.push_back(b.pending.front().first);
        b.pending.pop_front();
        ++spent;
      }
      std::vector<Frame> frames(spans.size());
      std::vector<std::exception_ptr> failure(spans.size());
      auto middle_of = [&](size_t i) { return 0.5 * (spans[i].first.first + spans[i].second.first); };
#pragma omp taskgroup
      for (size_t i = 0; i < spans.size(); ++i) {
#pragma omp task firstprivate(i) shared(spans, frames, failure, middle_of)
        try {
          frames[i] = examine(middle_of(i), false);
        } catch (...) {
          failure[i] = std::current_exception();
        }
      }
      for (size_t i = 0; i < spans.size(); ++i) {
        if (failure[i]) {
          b.failure = failure[i];
          return spent;
        }
        const std::pair<double, FrameTopology> middle{middle_of(i), frames[i].topology};
        b.frames.emplace_back(middle.first, frames[i]);
        if (level + 1 >= kBisections) continue;
        if (spans[i].first.second != middle.second) b.pending.push_back({{spans[i].first, middle}, level + 1});
        if (middle.second != spans[i].second.second) b.pending.push_back({{middle, spans[i].second}, level + 1});
      }
    }
    return spent;
  }

  bool crosses(const Slice& frame) const {
    try {
      return !self_intersections(frame.vertices, frame.faces, 1, tolerance_).empty();
    } catch (const std::exception&) {
      return true;  // not even a closed manifold there
    }
  }

  Frame examine(double t, bool look_for_crossings) {
    Frame out;
    index();
    const Slice frame = slicer_.slice_shape(axis_, t);
    out.topology = topology_of(frame.vertices, frame.faces);
    out.crossing = look_for_crossings && crosses(frame);
    return out;
  }

  void record(double t, const Frame& frame) {
    const FrameTopology& topology = frame.topology;
    checked_[t] = topology;
    ++report_.frames_checked;
    if (topology.euler < least_euler_ || topology.euler > most_euler_ || topology.pieces > most_pieces_)
      report_.noise_frames.push_back(t);
    if (topology.cavities > most_cavities_) {
      report_.bubble_frames.emplace_back(t, topology.cavities - most_cavities_);
      report_.largest_bubble_fraction =
          std::max(report_.largest_bubble_fraction, topology.cavity / std::max(topology.solid, 1e-300));
    }
    if (frame.crossing) report_.crossing_frames.push_back(t);
  }

  MorphReport& report_;
  Slicer slicer_;
  std::once_flag indexed_;
  int axis_;
  Index least_euler_ = 0, most_euler_ = 0, most_pieces_ = 0, most_cavities_ = 0;
  double tolerance_ = 0;
  std::map<double, FrameTopology> checked_;
};

// kSpreadFrames times evenly inside [t0, t1], coarse to fine: the one
// nearest the middle, then each time the one farthest from those taken and
// the range's ends (the quarters, the eighths, ...; ties to the earlier).
// The frames checked for crossings come first, and the costly frames first
// to the cores.
std::vector<double> spread_times(double t0, double t1) {
  std::vector<int> order;
  std::vector<bool> taken(kSpreadFrames + 1, false);
  while (static_cast<int>(order.size()) < kSpreadFrames) {
    int best = 0;
    double best_gap = -1;
    for (int i = 1; i <= kSpreadFrames; ++i) {
      if (taken[i]) continue;
      // In units of a frame's spacing: the range's ends at 0 and kSpreadFrames + 1.
      double gap = std::min(i, kSpreadFrames + 1 - i);
      for (const int j : order) gap = std::min(gap, static_cast<double>(std::abs(i - j)));
      if (order.empty()) gap = -std::abs(2 * i - (kSpreadFrames + 1));  // the first: the middle
      if (gap > best_gap || best == 0) best = i, best_gap = gap;
    }
    taken[best] = true;
    order.push_back(best);
  }
  std::vector<double> times;
  for (const int i : order) times.push_back(t0 + (t1 - t0) * i / (kSpreadFrames + 1));
  return times;
}

}  // namespace

void check_frames(const Complex& manifold, double t0, double t1, const PointMatrix& VS, const SimplexMatrix& FS,
                  const PointMatrix& VT, const SimplexMatrix& FT, MorphReport& report,
                  const std::vector<std::function<void()>>& alongside, int crossing_frames,
                  const std::function<bool()>& check_the_rest, const std::vector<double>& closer) {
  FrameChecks checks(manifold, VS, FS, VT, FT, report);
  const std::vector<double> spread = spread_times(t0, t1);
  const long crossing_count = std::clamp(crossing_frames, 0, kSpreadFrames);
  // The closer frames in the same loop as the spread ones (after them: the
  // first crossing_count are the spread's), so that no core waits between.
  std::vector<double> first = spread;
  first.insert(first.end(), closer.begin(), closer.end());
  checks.check(first, crossing_count, alongside);
  if (crossing_count < kSpreadFrames && check_the_rest && check_the_rest())
    checks.check_crossings(std::vector<double>(spread.begin() + crossing_count, spread.end()));
  checks.bisect_changes();
  checks.finish();
}

}  // namespace animanifold

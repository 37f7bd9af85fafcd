// The steps of the field method (morph_field.hpp), shared by its files:
// free points and the conforming ends (morph_field_points.cpp), the slabs of
// the space-time triangulation (morph_field_slabs.cpp), the blend's
// schedule in time (morph_field_timing.cpp).
#pragma once

#include "animanifold/morph.hpp"
#include "signed_distance.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace animanifold::morph_field {

using Simplex4 = std::array<Index, 5>;

// A deterministic value in [-0.5, 0.5) of four integers: jitter that makes
// point sets and field values general without randomness.
double jitter(std::int64_t i, std::int64_t j, std::int64_t k, int axis);

// Field values are scaled by 1 + kValueJitter * jitter(point, layer): inputs
// with symmetries (a torus's planar quads, points mirrored in a plane, equal
// values around a ring) would otherwise put the corners of a piece of the
// zero set on parallel edges at equal shares, a flat tet. The jitter moves
// the zero set by a ten-thousandth of the distance to the nearest input.
constexpr double kValueJitter = 1e-4;

// `value` scaled by 1 + kValueJitter * jitter(point, layer, salt).
inline double jittered(double value, Index point, int layer, std::int64_t salt = 0x5eed) {
  return value * (1.0 + kValueJitter * jitter(point, layer, salt, 0));
}

// The blend at weight w of the distances s to S and t to T: (1 - w) s + w t,
// less `widening` x 4 w (1 - w) (middle_widening()): zero at the ends, the
// whole widening at the middle.
inline double blend(double s, double t, double w, double widening) {
  return (1 - w) * s + w * t - 4 * widening * w * (1 - w);
}

// How deep the middle frame is at least, as a share of the thinner input's
// depth. A cone inside a torus's hole (Blender's primitives as added) or
// two inputs that barely meet have a convex blend that is empty, or all but
// empty, around the middle (its zero set is where s + t = 0, which needs
// points inside one input as deep as they are far from the other): the
// shape shrank to a thread and vanished for a quarter of the range before
// the other grew from it. Deep enough, the middle's zero set also keeps off
// the floor of the valley s + t has between two inputs, where the
// distances' slopes cancel and a level set is sampled as crumpled sheets.
constexpr double kMiddleDepth = 0.5;

// Inputs farther apart than twice this share of the thinner input's depth
// are not widened: the middle would be a sheet along the valley's floor
// between them; such inputs are dissolved where each stands
// (MorphReport::inputs_apart).
constexpr double kMiddleReach = 1.0;

// How much the blend is widened at the middle (blend()), from the distances
// s to S and t to T at points spread evenly over the box (the lattice's
// candidates, each standing for the same volume): the least that takes the
// middle's depth (the deepest -(s + t) / 2, plus the widening) to
// kMiddleDepth x the thinner input's (the deepest -s, -t), but not past
// taking as many of the points inside the middle ((s + t) / 2 below the
// widening) as the larger input holds. 0 where the middle is that deep
// already (inputs that overlap well; a middle that holds less than either
// input but is deep keeps its shape) and where the inputs lie too far
// apart (kMiddleReach). Points outside both inputs within twice the
// widening of the two together are inside the middle frame: the shape
// passes through the space between the inputs. A point outside both is
// inside a frame only if it lies within the widening of one of them
// ((1 - w) s + w t is at least the smaller of s, t, and 4 w (1 - w) at
// most 1).
double middle_widening(const Eigen::VectorXd& s, const Eigen::VectorXd& t);

// Per vertex, the largest circumradius of the triangles around it.
Eigen::VectorXd vertex_circumradius(const PointMatrix& V, const SimplexMatrix& F);

// ---------------------------------------------------------------- free points

struct Lattice {
  PointMatrix source, target;  // the free points each end keeps
  // The signed distances to S and to T at each kept point (the lattice's
  // test measured them), per end.
  Eigen::VectorXd source_s, source_t, target_s, target_t;
  PointMatrix corners;         // the box's, in both
  double spacing = 0;
  double widening = 0;         // middle_widening() of the distances at the lattice
};

// A jittered body-centred cubic lattice at `spacing` over a box around both
// inputs: dense where the zero set passes at some time (inside one input
// and outside the other, or near either: the convex blend is of one sign
// elsewhere; where it is widened, also outside both within reach of the
// middle's widening) and sparse elsewhere; each end keeps the points clear
// of its input (outside the diametral spheres of its faces, which the
// conforming mesher would otherwise split; from faces several lattice
// spacings across, only a spacing and a quarter: those it splits).
Lattice lattice_points(const PointMatrix& VS, const SimplexMatrix& FS, const SignedDistance& dS, const PointMatrix& VT,
                       const SimplexMatrix& FT, const SignedDistance& dT, double spacing, double size);

// Per point, whether it lies outside the diametral spheres of the faces of
// the surface (V, F) nearest to it (with a margin): a free point there does
// not make the conforming mesher split the surface. `d` is its signed distance.
std::vector<bool> clear_of_surface(const PointMatrix& points, const PointMatrix& V, const SimplexMatrix& F,
                                   const SignedDistance& d);

// Points on both sides of the surface (V, F), one per vertex and side, just
// clear of its faces' diametral spheres: the field near the input is
// resolved at the input's own scale (the frames just after t0 are offsets
// of it). Points whose side test disagrees or that come too close to the
// surface elsewhere (a thin part) are left out.
PointMatrix surface_shell(const PointMatrix& V, const SimplexMatrix& F, const SignedDistance& d);

struct EndMesh {
  PointMatrix points;             // the input's vertices, its free points, the box corners, Steiner points
  SimplexMatrix constraints;      // the input's faces refined (S'), oriented as the input's
  IndexVector constraint_parent;  // the input face each lies in
  std::vector<bool> on_surface;   // vertices of S': where the field is exactly zero at the end
  Index input_points = 0;  // the input's vertices: the first rows of `points`, never moved
  Index free_points = 0, steiner_points = 0;
  Index flat_cell_points = 0, flat_cells = 0;  // ConformingDelaunay's
};

// The conforming Delaunay tetrahedralization of one input with its free
// points and the box corners (TetGen -D, in a child process). Throws
// MeshingError naming the input (`name`) when it fails (TimeLimitError when
// TetGen ran past `mesher_time_limit`, see conforming_delaunay_3d).
EndMesh conform_end(const PointMatrix& V, const SimplexMatrix& F, const PointMatrix& free, const PointMatrix& corners,
                    const char* name, const std::function<void()>& while_meshing, double mesher_time_limit);

// One input and its free points, for conform_ends().
struct EndInput {
  const PointMatrix& V;
  const SimplexMatrix& F;
  const PointMatrix& free;
};

// Runs beside(stop_poll) on a thread of its own and here() on the calling
// thread, when the thread setting allows two (else beside(poll), then
// here()). Only the calling thread polls `poll` (Python sees Ctrl-C on its
// main thread alone): here() is given it, and it is called about every
// kWaitTick seconds while this thread waits for beside(). When here() or
// `poll` throws Cancelled, beside's stop_poll throws Cancelled at its next
// call (a child process's wait polls it, see isolated.hpp); other failures
// of here() let beside() finish. beside()'s own failure is thrown first, as
// when the two run in turn.
void side_by_side(const std::function<void(const std::function<void()>&)>& beside, const std::function<void()>& here,
                  const std::function<void()>& poll);

// Gives points of the two ends that coincide but for rounding (at most
// 1e-12 of the size apart: Steiner points the mesher placed on a face the
// inputs share, computed from different neighbours) one position. Two such
// pairs are the corners of a quad in space-time that is flat but for
// rounding, and the fill's 4-simplices over it are flat too: the zero set
// there has no certificate. The target's points move onto the source's, or
// (where that costs the target a face, cocircular points on the shared face
// tying the other way) the source's onto the target's; an input's own
// vertices never move (the other end's point moves onto one, and two input
// vertices stay as they are). Where either way costs an end a face, nothing
// moves. Returns how many points moved.
Index share_coincident_points(EndMesh& source, EndMesh& target);

// Both ends' conforming tetrahedralizations (conform_end), the source's (0)
// beside the target's (1) (side_by_side): each is the same serial work
// either way, so are the bits. A cancel stops both meshers.
std::array<EndMesh, 2> conform_ends(const EndInput& source, const EndInput& target, const PointMatrix& corners,
                                    const std::function<void()>& while_meshing, double mesher_time_limit);

// ---------------------------------------------------------------- slabs

// The 4 positive 4-simplices of the prism over the positive tet `c`: point
// v's copies are bottom + v and top + v; split by the staircase over the
// points in ascending `rank` (per point; ties and no rank: ascending v). Any
// order common to a slab's prisms keeps the slab conforming.
void prism_simplices(const Index* c, Index bottom, Index top, Simplex4* out, const double* rank = nullptr);

// The order of a slab's points (per point of `cells`; ascending) that its
// prisms' staircases follow (prism_simplices), from the field at the slab's
// bottom and top layers. At a time s between the layers, the staircase puts
// a node on every edge (i, j) of a cell, i before j, at (1 - s) x_i + s x_j,
// valued (1 - s) bottom_i + s top_j, not the value of each point interpolated
// in time there (the frames preserve_topology judges): where both ends have
// one sign and the node the other, the frame is widened or cut there. Points
// come in descending order of how much their field grows across the slab,
// so a node is never above the interpolation: the solid is only ever
// widened a little, never cut by a tunnel or into fragments. Widening is
// not free of topology: where a deep point comes before a shallow, slow
// one that crosses the same way, the node between them keeps the solid's
// sign after both have crossed (before both, for points joining it), and
// can stand for a while as an island (the in-slab transients the dense
// frame surveys still find; the other order cuts instead). And a point
// positive on both layers (one preserve_topology holds out of the negative
// region to keep two parts apart) is widened across from a neighbour that
// joins the region if it comes first, from one that leaves it if it comes
// last: the parts it keeps apart met within the slab, a handle or a merge
// for a while. So it comes last where at least as many of its neighbours in
// the cells join as leave, first where more leave: where they all join or
// all leave, no node takes the solid across it.
std::vector<double> staircase_rank(const SimplexMatrix& cells, const Eigen::VectorXd& bottom,
                                   const Eigen::VectorXd& top);

// Whether the 4-simplex `s` (rows of X, time last) is flat but for
// rounding: its volume, with time scaled by `time_scale` (the shapes' size
// over the range, so that the answer does not depend on the units of time),
// at most 1e-12 of its longest edge to the fourth. The zero set in such a
// simplex is a sheet in the simplex's hyperplane that the roundings of its
// cuts place, and it can fold onto its neighbours' with zero thickness
// (morph_field.hpp's certificate). On the test pairs every simplex the zero
// set passes through is above 1e-7 of that (mostly above 1e-3); the prisms
// over a flat cell of an end (a planar quad's cocircular corners) are at
// 1e-15 to 1e-17.
bool flat_to_rounding(const PointMatrix& X, const Simplex4& s, double time_scale);

struct Fill {
  SimplexMatrix simplices;                   // over [P_S; P_T]
  SimplexMatrix source_cells, target_cells;  // its end facets: K_S over P_S, K_T over P_T, positive in R^3
};

// The Delaunay triangulation in R^4 of P_S at time 0 and P_T at `thickness`.
Fill fill_slab(const PointMatrix& PS, const PointMatrix& PT, double thickness);

// The signed distances to S (s) and to T (t) at an end's points, kept as
// points are appended to the end (refinement, then the chords' middles):
// each point's pair is measured once.
struct EndDistances {
  Eigen::VectorXd s, t;
  double widening = 0;  // the blend's (blend(), middle_widening())
  // The blend at point v, or of a pair of distances, at weight w.
  double blend(Index v, double w) const { return morph_field::blend(s(v), t(v), w, widening); }
  double blend(double sv, double tv, double w) const { return morph_field::blend(sv, tv, w, widening); }
  // Measures the points of `points` beyond those measured so far.
  void extend(const PointMatrix& points, const SignedDistance& dS, const SignedDistance& dT);
};

// Points where a half's tetrahedralization (`cells` over `points`) samples
// the blend too coarsely at some of the half's `weights`: the middles of
// edges that bridge the zero set (their ends of one sign, their middle of
// the other) or are crossed by it and longer than 1.5 `spacing`, where they
// are clear of the end's input (V, F; `own` its signed distance). Edges
// between two points of the input are the chords' business (split_chords).
// `at_points` holds the distances at `points`.
PointMatrix refinement_points(const SimplexMatrix& cells, const PointMatrix& points, const std::vector<bool>& on_surface,
                              const PointMatrix& V, const SimplexMatrix& F, const SignedDistance& own,
                              const SignedDistance& dS, const SignedDistance& dT, const EndDistances& at_points,
                              const std::vector<double>& weights, double spacing);

// Free points beside the flat cells of an end's tetrahedralization (`cells`
// over `points`): tets whose four corners are on the input and lie in one
// plane but for rounding. Inputs on a grid (voxel models, CAD parts) have
// four cocircular points in one plane across a step or a hole, and the
// Delaunay triangulation then may hold the flat tet between them; the
// prisms over it are flat 4-simplices, and the zero set crossing them folds
// onto its neighbours (no certificate, and frames that run through
// themselves). Per flat cell, a point on each side of its plane, on the
// normal through its centre, at `reach` x about a third of its size: one
// inside the circumsphere of the tet beside the flat one breaks the tie.
// Whether a point keeps the input's faces is add_free_points()'s to judge
// (morph_field.cpp): the points are close to the input by nature.
PointMatrix points_off_flat_cells(const SimplexMatrix& cells, const PointMatrix& points,
                                  const std::vector<bool>& on_surface, double reach);

// A half's tetrahedralization refined by stellar splits of its chords and
// of its curved edges (chapter 6), for the stacks of prisms of that half
// (morph_field.hpp).
struct RefinedCells {
  SimplexMatrix cells;                      // over the points, then the new ones
  PointMatrix new_points;                   // #new by 3: ids n, n+1, ...
  std::vector<std::vector<Index>> splits;   // per new point, the face it split (ids then)
  std::vector<std::vector<double>> shares;  // per new point, its barycentric coordinates in that face
  Index outside_chords = 0, flat_chords = 0;  // chords left as they are
};

// Splits the inside chords of the end facet (`cells` over `points`, the
// conforming end with its input's refined faces `constraints`): edges, then
// triangles, then tets whose corners are all on the input and that are not
// its own, where they lie inside it and not in it but for rounding (the
// field would be zero along them at the end). `own` is the input's signed
// distance.
RefinedCells split_chords(const SimplexMatrix& cells, const PointMatrix& points, const std::vector<bool>& on_surface,
                          const SimplexMatrix& constraints, const SignedDistance& own);

// Splits at their middles, in up to `rounds` rounds, the edges of
// `refined` (over `points`, then its new points) from a point of the input
// to one off it, no shorter than `shortest`, along which the blend at one
// of `weights` bends: where the zero set passes the edge or both its ends
// are within half its length of zero at that weight, and the blend at its
// middle is more than `tolerance` off the mean of its ends' but on the same
// side of zero, at each of `weights` and of `slaved` (the layers where the
// splits' points take the unsplit cells' values, slave_split_points). So a
// split moves the zero set within the cells it splits and changes the
// topology of no layer: preserve_topology sees the changes it saw without
// it, and slaving changes no sign. (A point put on the other side would
// make a layer's topology finer than preserve_topology follows from layer
// to layer: held spikes at a cylinder's rims that go at once, a pop; or
// two pieces held from the slaved layer to the fill.) The frames
// near an end are offsets of the input, and they run through the tets its
// faces bound; a big flat face leaves those tets a lattice spacing deep
// (free points keep clear of its diametral sphere), and inside an input
// with sharp edges the distance is creased along the medial planes from
// them. Sampled only at the tets' corners, an offset's rim is then cut
// into a saw-tooth a lattice spacing deep (Blender's cube into its
// cylinder, frame after frame). The splits are stellar (chapter 6), so the
// input's faces stay; `distances` holds those at all points and gets the
// middles'. Returns how many points were added.
Index split_curved_edges(RefinedCells& refined, const PointMatrix& points, const std::vector<bool>& on_surface,
                         const std::vector<double>& weights, const std::vector<double>& slaved,
                         const SignedDistance& dS, const SignedDistance& dT, EndDistances& distances, double tolerance,
                         double shortest, int rounds);

// Free points at the middles of the chords split_chords() would split
// (`cells` over `points`, the conforming end), where the unsplit cells
// sample the blend at one of `weights` with the wrong sign there: the fill's
// end facet keeps the chords unsplit, so without a point inside them the
// layers next to the fill lose what lies between the input's points (a thin
// box's inside, whose tets have only the input's points for corners, was
// carved away there: half its volume). The chords' own points keep the
// stack's layers right, not the fill's. `own` is the end's input's signed
// distance; a point is moved off the middle by a little, within its depth
// in the input. Whether it keeps the input's faces is add_free_points()'s
// to judge.
PointMatrix undersampled_chords(const SimplexMatrix& cells, const PointMatrix& points,
                                const std::vector<bool>& on_surface, const SimplexMatrix& constraints,
                                const SignedDistance& own, const SignedDistance& dS, const SignedDistance& dT,
                                const EndDistances& at_points, const std::vector<double>& weights, double spacing);

// The slab from a half's refined layer to the fill's (unrefined) one: prisms
// over `cells` (the fill's end facet over its n points) with `splits`
// replayed on the refined layer's copies. Local ids: the refined layer's
// points 0..refined_count-1 (its first n the unrefined points, then the new
// ones), the unrefined layer's refined_count + v. `rank` (per unrefined
// point, optional) orders each prism's staircase as prism_simplices'.
std::vector<Simplex4> transition_slab(const SimplexMatrix& cells, const std::vector<std::vector<Index>>& splits,
                                      Index n, Index refined_count, bool refined_at_bottom,
                                      const double* rank = nullptr);

// ---------------------------------------------------------------- topology

// The Betti numbers (pieces, handles, cavities) of the region where `field`
// (per point of the tetrahedralization `cells`) is negative.
std::array<Index, 3> betti_numbers(const SimplexMatrix& cells, const Eigen::VectorXd& field);

// Keeps a half's zero set free of topological noise: from layer `first` on,
// each layer's field (per point of `cells`, a tetrahedralization) changes
// sign from the layer before where the change is simple (it keeps the
// topology of the negative region and of the positive one: the point's link
// splits into two disks), taken in the order the changes happen between the
// layers; where it is not, only if every Betti number of the negative region
// it changes goes down and stays at or above `floor_betti` (the least of the
// two ends': going from an end towards the middle, the topology only sheds
// what the other end does not have, so the two halves meet with the same),
// or, for a point of the layer's `bridges` (per layer, empty for none)
// joining the negative region, stays at or below `ceiling_betti` (the
// largest of the two ends'): a bridge may close a loop for a while, and the
// connection it replaces then goes as a handle, not as a split.
// The rest keep their sign at -floor (or kHeldOutside floors above zero)
// and try again at the next layer. Of the points held in the negative
// region, those whose removal has since become simple (a thread to a part
// that has gone) leave from the thread's free end, at least a share of
// 1 / (layers left) of them on each layer, first between the layers: none
// is left on the last layer (the fill's). Returns how many (point, layer)
// values were held.
Index preserve_topology(const SimplexMatrix& cells, std::vector<Eigen::VectorXd>& field, int first, double floor,
                        const std::array<Index, 3>& floor_betti, const std::array<Index, 3>& ceiling_betti,
                        const std::vector<std::vector<bool>>& bridges);

// Every edge of a tetrahedralization once, ends sorted, in sorted order.
std::vector<std::array<Index, 2>> tet_edges(const SimplexMatrix& cells);

// Where the region where `field` (per point of the tetrahedralization
// `cells` over `points`) is negative falls into more than `pieces` pieces:
// the lowest paths (least highest value) that join them until `pieces` are
// left, as segments between points (Kruskal's spanning forest by edge
// height, stopped there, its non-negative branches pruned), and the highest
// value on them. The saddles of the field between its pieces; no segment
// when there are no more than `pieces`.
struct Bridge {
  std::vector<std::array<Eigen::Vector3d, 2>> segments;
  std::vector<bool> into_piece;  // per segment: its second end is a piece's (negative)
  double height = 0;
};
Bridge bridge_between_pieces(const SimplexMatrix& cells, const PointMatrix& points, const Eigen::VectorXd& field,
                             Index pieces);

// Whether each of a set of points (rows) lies outside both inputs.
using OutsideBoth = std::function<Eigen::Array<bool, Eigen::Dynamic, 1>(const PointMatrix&)>;

// Takes a bridge's bump (`bump`, per point) off both ends of each edge that
// crosses a gap between the inputs: one end lowered by the bump and the
// other by it too or `negative` (the blend is below zero there on some
// layer), an edge the balls about its ends (of their depth inside the
// inputs) leave partly uncovered, with a point of the uncovered part outside
// both (sampled at kGapSamples points). Both ends negative, the negative
// region would span the gap however the values are lifted
// (keep_bump_inside), so both ends keep the blend: the bridge joins the
// inputs where they overlap. Returns how many edges lost their bump.
constexpr int kGapSamples = 5;
Index keep_gaps_open(const PointMatrix& points, const std::vector<std::array<Index, 2>>& edges,
                     const EndDistances& distances, const OutsideBoth& outside_both,
                     const std::vector<bool>& negative, Eigen::VectorXd& bump);

// Lifts the points a bridge's bump lowered on layer `layer` of `field`
// (`bump` > 0 there; `unbumped` their values before it) as far as keeps its
// zero inside the inputs. On an edge from a lowered point p, `inside` deep
// in an input (the ball of that radius about p lies in the inputs), to a
// point q with a value v > 0 on the layer or a neighbouring one (a slab's
// cells join the two), the zero falls within `inside` of p while p's value
// is no lower than -inside v / (length - inside); an edge that the balls
// about its two ends cover needs nothing. So the bridge never reaches into
// a shared hole (validity 3), and still takes every lowered point below
// zero: at least `floor` below (jittered like every value), which lets the
// zero pass a point on an input's surface by a small share of an edge.
// Lifting leaves the positive values as they are, so the layers can be
// lifted in any order once all are lowered.
void keep_bump_inside(const PointMatrix& points, const std::vector<std::array<Index, 2>>& edges,
                      const EndDistances& distances, const Eigen::VectorXd& bump, std::vector<Eigen::VectorXd>& field,
                      size_t layer, const Eigen::VectorXd& unbumped, double floor);

// ---------------------------------------------------------------- through the inputs

// A path along a tetrahedralization's edges is longer than the straight
// line by up to a few of its edges; this many lattice spacings of it do not
// count, so that beside the overlap of the inputs, where the straight line
// stays inside, the blend keeps the straight distance.
constexpr double kThroughSlack = 2.0;

// The distances the blend uses (s to S, t to T, per point of the
// tetrahedralization `cells` over `points`), each lengthened, at a point
// inside the other input only, to the path inside that input from where the
// two overlap (less kThroughSlack `spacing`s). A part of T outside S (a
// limb, a tail) is then the farther from S the farther it reaches from the
// overlap: it grows from its root and retracts from its free end, where by
// the straight distance a tip that curls back near S would outlast the
// limb's middle, and be held to the body by a thread until it goes at once.
// Points outside both inputs keep their distances: the blend stays positive
// there, and shared holes stay empty.
void distances_through_inputs(const SimplexMatrix& cells, const PointMatrix& points, double spacing,
                              Eigen::VectorXd& s, Eigen::VectorXd& t);

// ---------------------------------------------------------------- timing

// The target's weight w in the blend at each share u of the range: the
// inverse of the zero set's accumulated motion, so that it moves at an even
// pace from the first frame to the last.
struct BlendSchedule {
  std::vector<double> u, w;  // increasing, from (0, 0) to (1, 1)
  double operator()(double at) const;
};

// The zero set of the blend at `samples` + 1 even weights (the inputs at the
// ends, level sets on K_S and K_T between), then at midpoints of intervals
// that move much faster than the mean (bisected a few rounds: fast events
// get samples of their own); the two-sided distance between consecutive
// ones, accumulated, and its inverse.
// `source_cells` over `PS` and `target_cells` over `PT` are the halves'
// tetrahedralizations; sS, tS (sT, tT) the signed distances to S and T at PS
// (PT); `widening` the blend's (blend()).
BlendSchedule motion_schedule(const PointMatrix& VS, const SimplexMatrix& FS, const PointMatrix& VT,
                              const SimplexMatrix& FT, const SimplexMatrix& source_cells,
                              const SimplexMatrix& target_cells, const PointMatrix& PS, const PointMatrix& PT,
                              const Eigen::VectorXd& sS, const Eigen::VectorXd& tS, const Eigen::VectorXd& sT,
                              const Eigen::VectorXd& tT, int samples, double widening = 0);

}  // namespace animanifold::morph_field

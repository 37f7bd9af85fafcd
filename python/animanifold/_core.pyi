# Type stub of the native module, generated with pybind11-stubgen (pip install pybind11-stubgen;
# PYTHONPATH=python pybind11-stubgen animanifold._core -o <dir> --ignore-all-errors). Regenerate after changing cpp/bindings.
"""
animanifold's native core: animation manifolds as simplicial complexes
"""
from __future__ import annotations
import collections.abc
import numpy
import numpy.typing
import typing
__all__: list[str] = ['BooleanError', 'Cancelled', 'Complex', 'Deformer', 'FillTriangulation', 'IntervalFrame', 'MorphMethod', 'MorphOptions', 'MorphReport', 'Perturbation', 'RefineOrder', 'Slice', 'Slicer', 'VoronoiSkeleton', 'affine_power', 'boundary_facets', 'boundary_vertices', 'check_closed_oriented', 'check_manifold', 'check_morph_frames', 'check_morph_input', 'closest_points', 'conforming_delaunay_2d', 'conforming_delaunay_3d', 'delaunay', 'delaunay_exact', 'dihedral_test', 'distances_to_surface', 'drop_component', 'dual_operator', 'edge_length_degeneracy', 'encroachments', 'external_skeleton_points', 'faces_intersecting_mesh', 'facet_adjacency', 'facets', 'frame_vertex_normals', 'graph_laplacian_weights', 'hole_space', 'intersect_solids', 'laplacian_system', 'make_voronoi_separable', 'missing_facets', 'morph', 'points_inside_solid', 'primal_weights', 'read_mesh', 'refine', 'self_intersections', 'signed_volumes', 'simplex_normals', 'simplex_qp', 'simplex_volumes', 'slice', 'smooth_slice', 'solid_measure', 'stitch', 'subdivide_frame', 'subdivide_manifold', 'subdivide_polyline', 'subtract_solid', 'vertex_normals', 'voronoi_skeleton', 'wedge', 'wrap', 'write_mesh']
class Complex:
    """
    Points (#V by D) and oriented simplices (#S by k+1) with per-vertex float and per-simplex integer attributes.
    """
    def __init__(self, points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], vertex_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"]] = {}, simplex_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"]] = {}) -> None:
        ...
    def validate(self) -> None:
        ...
    @property
    def points(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        ...
    @property
    def simplex_attributes(self) -> dict:
        ...
    @property
    def simplices(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]:
        ...
    @property
    def vertex_attributes(self) -> dict:
        ...
class Slice:
    """
    One iso-slice (frame) of a manifold.
    """
    @property
    def edge_parameter(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        ...
    @property
    def face_attributes(self) -> dict[str, typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]]:
        ...
    @property
    def face_simplex(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]:
        ...
    @property
    def faces(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]:
        ...
    @property
    def normals(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        ...
    @property
    def vertex_attributes(self) -> dict[str, typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]]:
        ...
    @property
    def vertex_edges(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]:
        ...
    @property
    def vertices(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        ...
class Slicer:
    """
    A manifold with its cached interval indices (one per slicing axis).
    """
    def __init__(self, manifold: Complex) -> None:
        ...
    def index_memory_bytes(self, axis: typing.SupportsInt | typing.SupportsIndex) -> int:
        ...
    def interval_frame(self, axis: typing.SupportsInt | typing.SupportsIndex, value: typing.SupportsFloat | typing.SupportsIndex) -> IntervalFrame:
        """
        The frame at `value` with its topology interval and rates; ValueError where it has none (a vertex coordinate, outside the manifold).
        """
    def slice(self, axis: typing.SupportsInt | typing.SupportsIndex, value: typing.SupportsFloat | typing.SupportsIndex, use_index: bool = True) -> Slice:
        ...
    def topology_interval(self, axis: typing.SupportsInt | typing.SupportsIndex, value: typing.SupportsFloat | typing.SupportsIndex) -> tuple[float, float] | None:
        """
        The open interval (lo, hi) around `value` without vertex coordinates (every slice in it has the same faces), or None where the faces change (a vertex coordinate, outside the manifold).
        """
class IntervalFrame:
    """
    A frame with how it moves inside its topology interval (lo, hi): at v in it, the slice has the same faces and vertex p is at slice.vertices[p] + (v - value) * rate[p] (vertex attributes and edge_parameter likewise, with attribute_rates and parameter_rate).
    """
    @property
    def attribute_rates(self) -> dict[str, typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]]:
        """
        Name -> (P, c): d attribute / d value.
        """
    @property
    def axis(self) -> int:
        ...
    @property
    def interval(self) -> tuple:
        """
        The open topology interval (lo, hi) around `value`.
        """
    @property
    def parameter_rate(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        (P,): d edge_parameter / d value.
        """
    @property
    def rate(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        (P, D-1): d vertices / d value.
        """
    @property
    def slice(self) -> Slice:
        """
        The Slice at `value`.
        """
    @property
    def value(self) -> float:
        """
        The value the slice was cut at.
        """
class MorphMethod:
    """
    How a morph fills the space between its inputs.
    
    Members:
    
      skeleton
    
      strip
    
      field
    """
    __members__: typing.ClassVar[dict[str, MorphMethod]]
    field: typing.ClassVar[MorphMethod]
    skeleton: typing.ClassVar[MorphMethod]
    strip: typing.ClassVar[MorphMethod]
    @typing.overload
    def __eq__(self, other: MorphMethod) -> bool:
        ...
    @typing.overload
    def __eq__(self, other: typing.Any) -> bool:
        ...
    def __getstate__(self) -> int:
        ...
    def __hash__(self) -> int:
        ...
    def __index__(self) -> int:
        ...
    @typing.overload
    def __init__(self, value: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    @typing.overload
    def __init__(self, arg0: str) -> None:
        ...
    def __int__(self) -> int:
        ...
    @typing.overload
    def __ne__(self, other: MorphMethod) -> bool:
        ...
    @typing.overload
    def __ne__(self, other: typing.Any) -> bool:
        ...
    def __repr__(self) -> str:
        ...
    def __setstate__(self, state: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    def __str__(self) -> str:
        ...
    @property
    def name(self) -> str:
        ...
    @property
    def value(self) -> int:
        ...
class FillTriangulation:
    """
    The seed methods' Delaunay fill.
    
    Members:
    
      cgal
    
      qhull
    """
    __members__: typing.ClassVar[dict[str, FillTriangulation]]
    cgal: typing.ClassVar[FillTriangulation]
    qhull: typing.ClassVar[FillTriangulation]
    @typing.overload
    def __eq__(self, other: FillTriangulation) -> bool:
        ...
    @typing.overload
    def __eq__(self, other: typing.Any) -> bool:
        ...
    def __getstate__(self) -> int:
        ...
    def __hash__(self) -> int:
        ...
    def __index__(self) -> int:
        ...
    @typing.overload
    def __init__(self, value: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    @typing.overload
    def __init__(self, arg0: str) -> None:
        ...
    def __int__(self) -> int:
        ...
    @typing.overload
    def __ne__(self, other: FillTriangulation) -> bool:
        ...
    @typing.overload
    def __ne__(self, other: typing.Any) -> bool:
        ...
    def __repr__(self) -> str:
        ...
    def __setstate__(self, state: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    def __str__(self) -> str:
        ...
    @property
    def name(self) -> str:
        ...
    @property
    def value(self) -> int:
        ...
class Perturbation:
    """
    How the seed methods put the inputs in general position.
    
    Members:
    
      hull_faces
    
      position
    """
    __members__: typing.ClassVar[dict[str, Perturbation]]
    hull_faces: typing.ClassVar[Perturbation]
    position: typing.ClassVar[Perturbation]
    @typing.overload
    def __eq__(self, other: Perturbation) -> bool:
        ...
    @typing.overload
    def __eq__(self, other: typing.Any) -> bool:
        ...
    def __getstate__(self) -> int:
        ...
    def __hash__(self) -> int:
        ...
    def __index__(self) -> int:
        ...
    @typing.overload
    def __init__(self, value: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    @typing.overload
    def __init__(self, arg0: str) -> None:
        ...
    def __int__(self) -> int:
        ...
    @typing.overload
    def __ne__(self, other: Perturbation) -> bool:
        ...
    @typing.overload
    def __ne__(self, other: typing.Any) -> bool:
        ...
    def __repr__(self) -> str:
        ...
    def __setstate__(self, state: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    def __str__(self) -> str:
        ...
    @property
    def name(self) -> str:
        ...
    @property
    def value(self) -> int:
        ...
class MorphOptions:
    """
    The morph's options (cpp/include/animanifold/morph.hpp documents each).
    """
    fan_flat_polygons: bool
    fill: FillTriangulation
    hold_stage: str
    method: MorphMethod
    perturbation: Perturbation
    def __init__(self) -> None:
        ...
    @property
    def field_layers(self) -> int:
        ...
    @field_layers.setter
    def field_layers(self, arg0: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    @property
    def field_resolution(self) -> float:
        ...
    @field_resolution.setter
    def field_resolution(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def hold_seconds(self) -> float:
        ...
    @hold_seconds.setter
    def hold_seconds(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def max_push(self) -> float:
        ...
    @max_push.setter
    def max_push(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def t0(self) -> float:
        ...
    @t0.setter
    def t0(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def t1(self) -> float:
        ...
    @t1.setter
    def t1(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
class MorphReport:
    """
    What the morph's checks found and what each stage cost (morph.hpp).
    """
    def __getitem__(self, arg0: str) -> typing.Any:
        ...
    def to_dict(self) -> dict:
        """
        The report as a dict of plain values (what the cache stores).
        """
class Cancelled(Exception):
    pass
class RefineOrder:
    """
    Order in which split tuples are applied (§6.3).
    
    Members:
    
      given
    
      degeneracy
    """
    __members__: typing.ClassVar[dict[str, RefineOrder]]
    degeneracy: typing.ClassVar[RefineOrder]
    given: typing.ClassVar[RefineOrder]
    @typing.overload
    def __eq__(self, other: RefineOrder) -> bool:
        ...
    @typing.overload
    def __eq__(self, other: typing.Any) -> bool:
        ...
    def __getstate__(self) -> int:
        ...
    def __hash__(self) -> int:
        ...
    def __index__(self) -> int:
        ...
    def __init__(self, value: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    def __int__(self) -> int:
        ...
    @typing.overload
    def __ne__(self, other: RefineOrder) -> bool:
        ...
    @typing.overload
    def __ne__(self, other: typing.Any) -> bool:
        ...
    def __repr__(self) -> str:
        ...
    def __setstate__(self, state: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    def __str__(self) -> str:
        ...
    @property
    def name(self) -> str:
        ...
    @property
    def value(self) -> int:
        ...
class VoronoiSkeleton:
    """
    Internal/external Voronoi skeleton (chapter 7).
    """
    @property
    def attachment(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]:
        ...
    @property
    def bisectors(self) -> int:
        ...
    @property
    def dihedral(self) -> dict:
        ...
    @property
    def discarded(self) -> int:
        ...
    @property
    def discarded_far(self) -> int:
        ...
    @property
    def discarded_nonlocal(self) -> int:
        ...
    @property
    def faces(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]:
        ...
    @property
    def iterations(self) -> int:
        ...
    @property
    def on_mesh(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]:
        ...
    @property
    def polygon(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]:
        ...
    @property
    def refined_faces(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]:
        ...
    @property
    def refined_vertices(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        ...
    @property
    def seconds_extraction(self) -> float:
        ...
    @property
    def seconds_separability(self) -> float:
        ...
    @property
    def separable(self) -> bool:
        ...
    @property
    def side(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]:
        ...
    @property
    def sites(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]:
        ...
    @property
    def splits(self) -> int:
        ...
    @property
    def vertices(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        ...
class Deformer:
    """
    Laplacian editing with a kept CHOLMOD factorisation.
    """
    def __init__(self, points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], anchors: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], handles: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"], method: str = 'dual', boundary: str = 'grow', lam: typing.SupportsFloat | typing.SupportsIndex = 0.1, xi: typing.SupportsFloat | typing.SupportsIndex = 0.001, ridge: typing.SupportsFloat | typing.SupportsIndex = 1e-08, constraint_weight: typing.SupportsFloat | typing.SupportsIndex = 0.0, zero_detail_vertices: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex] = []) -> None:
        ...
    def deform(self, transform: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], steps: typing.SupportsInt | typing.SupportsIndex = 1) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        ...
    def deform_to(self, positions: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], steps: typing.SupportsInt | typing.SupportsIndex = 1) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        ...
    def restore(self, max_iterations: typing.SupportsInt | typing.SupportsIndex = 50, tolerance: typing.SupportsFloat | typing.SupportsIndex = 1e-06) -> dict:
        ...
    @property
    def anchors(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]:
        ...
    @property
    def delta(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        ...
    @property
    def handles(self) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]:
        ...
    @property
    def info(self) -> dict:
        ...
    @property
    def laplacian(self) -> tuple:
        ...
    @property
    def points(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        ...
class BooleanError(RuntimeError):
    pass
def affine_power(transform: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], s: typing.SupportsFloat | typing.SupportsIndex) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
    """
    T^s: the fraction s of an affine (D+1)x(D+1) transform (polar factors about its fixed point).
    """
def boundary_facets(simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]:
    ...
def boundary_vertices(simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], vertex_count: typing.SupportsInt | typing.SupportsIndex) -> numpy.typing.NDArray[numpy.bool]:
    ...
def check_closed_oriented(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> None:
    ...
def check_manifold(simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> dict:
    ...
def check_morph_frames(manifold: Complex, t0: typing.SupportsFloat | typing.SupportsIndex, t1: typing.SupportsFloat | typing.SupportsIndex, source_points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], source_faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], target_points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], target_faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], budget_seconds: typing.SupportsFloat | typing.SupportsIndex = 60.0) -> MorphReport:
    """
    The morph's frame checks (morph_validity.hpp) on a manifold (tets in R^4) that should run from the source at t0 to the target at t1: a MorphReport with frames_checked, frames_capped, topology_changes, crossing_frames, bubble_frames, largest_bubble_fraction and noise_frames filled in.
    """
def check_morph_input(vertices: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], faces: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"], name: str) -> None:
    """
    Raises ValueError naming the shape (`name`) and the face or vertex when morph() would refuse it.
    """
def closest_points(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]]:
    """
    (distance, face, barycentric) of the closest point on a closed triangle mesh to each point (#P, 3): its unsigned distance, the face it lies on, and its barycentric coordinates in that face's corners.
    """
def conforming_delaunay_2d(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], edges: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> dict:
    """
    Conforming Delaunay triangulation (CGAL).
    """
def conforming_delaunay_3d(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> dict:
    """
    Conforming Delaunay tetrahedralization (TetGen -pD).
    """
def delaunay(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"]) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"], int, typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]]:
    """
    (simplices, flat_count, flat_simplices): Delaunay triangulation in any dimension (Qhull).
    """
def delaunay_exact(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"]) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"], int, typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]]:
    """
    (simplices, flat_count, flat_simplices): Delaunay triangulation in R^3 or R^4 (CGAL).
    """
def dihedral_test(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], limit: typing.SupportsFloat | typing.SupportsIndex = 0.7853981633974483) -> dict:
    ...
def distances_to_surface(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    Distance from each point to the surface (triangles in R^3, segments in R^2); inf without faces.
    """
def drop_component(normals: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], axis: typing.SupportsInt | typing.SupportsIndex) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
    ...
def dual_operator(simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], vertex_count: typing.SupportsInt | typing.SupportsIndex) -> tuple[tuple, typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]]:
    """
    (D as CSR, neighbours (#S by n+1), ghost_facets (#G by 2)).
    """
def edge_length_degeneracy(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    Variance of each simplex's edge lengths over their squared mean (§6.3). #S vector.
    """
def encroachments(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], neighbourhood: typing.SupportsInt | typing.SupportsIndex = 2, in_plane_angle: typing.SupportsFloat | typing.SupportsIndex = 0.3) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
    """
    (rows, distance): rows (vertex, a, b, c or -1, type 2/3/4) per encroached simplex and its closest encroacher.
    """
def external_skeleton_points(points: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], faces: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"], gap: typing.SupportsFloat | typing.SupportsIndex) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
    """
    Vertices of the external Voronoi skeleton off the surface, at least gap apart (§8.6.1).
    """
def faces_intersecting_mesh(faces_vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], mesh_faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.bool], "[m, 1]"]:
    """
    Per face (triangles in R^3, segments in R^2): does it intersect the mesh? CGAL exact predicates.
    """
def facet_adjacency(simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]]:
    """
    (neighbour, opposite): simplex across each facet and its facet index, -1 on the boundary.
    """
def facets(simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]:
    """
    All facets (#S*k by k-1), facet i of simplex s at row s*k+i, oriented by the rule of §2.4.
    """
def frame_vertex_normals(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
    """
    Area-weighted unit vertex normals of a frame (triangles in R^3, segments in R^2).
    """
def graph_laplacian_weights(edges: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], lam: typing.SupportsFloat | typing.SupportsIndex = 0.1, xi: typing.SupportsFloat | typing.SupportsIndex = 0.001, ridge: typing.SupportsFloat | typing.SupportsIndex = 1e-08) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    Eq. 4.2 weights of one vertex from its one-ring edges v_j − v_i (k by D).
    """
def hole_space(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]]:
    """
    (vertices, faces) of CH(C) \\ C for a closed outward mesh (triangles in R^3) or counter-clockwise polygons (edges in R^2); empty arrays when C is convex.
    """
def intersect_solids(vertices_a: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces_a: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], vertices_b: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces_b: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"]]:
    """
    (vertices, faces) of A ∩ B for closed solids (both 3D meshes or both 2D polygons).
    """
def laplacian_system(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], method: str = 'dual', lam: typing.SupportsFloat | typing.SupportsIndex = 0.1, xi: typing.SupportsFloat | typing.SupportsIndex = 0.001, ridge: typing.SupportsFloat | typing.SupportsIndex = 1e-08, zero_detail_vertices: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex] = []) -> tuple[tuple, typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]]:
    """
    (L as CSR, delta): L V = Δ for the input.
    """
def make_voronoi_separable(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], max_iterations: typing.SupportsInt | typing.SupportsIndex = 4, neighbourhood: typing.SupportsInt | typing.SupportsIndex = 2, in_plane_angle: typing.SupportsFloat | typing.SupportsIndex = 0.3) -> dict:
    ...
def missing_facets(simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, 1]"]:
    """
    Rows of faces that are not faces of any simplex (Theorem 5.2.1).
    """
def morph(source_points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], source_faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], target_points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], target_faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], options: typing.Any = None, progress: typing.Any = None, interrupted: typing.Any = None, **kwargs) -> tuple[Complex, MorphReport]:
    """
    Morph between two closed shapes: (manifold Complex, MorphReport). `options` (a MorphOptions; fields may also be given by keyword, enums by name: method='field'). `progress(stage, fraction)` is called between stages and `interrupted()` about every 0.1 s while a mesher runs; False from the one, True from the other, cancels (raises Cancelled).
    """
def points_inside_solid(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.bool], "[m, 1]"]:
    """
    Whether each point (#P, 3) lies inside (or on) the closed outward triangle mesh; cavities and tunnels are outside.
    """
def primal_weights(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], method: str, lam: typing.SupportsFloat | typing.SupportsIndex = 0.1, xi: typing.SupportsFloat | typing.SupportsIndex = 0.001, ridge: typing.SupportsFloat | typing.SupportsIndex = 1e-08) -> tuple:
    """
    Primal weights W (#V by #V) as CSR (indptr, indices, data, shape).
    """
def read_mesh(path: str) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"], int]:
    """
    (vertices, triangles, polygons_triangulated) of an OFF/OBJ/PLY/STL file, via CGAL.
    """
def refine(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], vertex_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"]], simplex_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"]], split_vertices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], split_barycentric: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], epsilon: typing.SupportsFloat | typing.SupportsIndex = 0.001, order: RefineOrder = ...) -> dict:
    """
    Barycentric refinement (chapter 6). split_vertices (T by m, -1 padded) and split_barycentric (T by m) are the split tuples; returns a dict of the refined arrays and the maps of animanifold/refine.hpp.
    """
def self_intersections(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], max_pairs: typing.SupportsInt | typing.SupportsIndex = 1, tolerance: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> list[tuple[int, int]]:
    """
    Pairs of faces of a closed shape that cross (not along shared edges/corners); max_pairs=0: all. tolerance > 0: only pairs that pass through each other by more than that (rounding left out).
    """
def signed_volumes(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    ...
def simplex_normals(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
    ...
def simplex_qp(H: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], g: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], lower: typing.SupportsFloat | typing.SupportsIndex, max_iterations: typing.SupportsInt | typing.SupportsIndex = 0) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"], float, int, bool]:
    """
    min ½wᵀHw + gᵀw s.t. Σw = 1, w >= lower → (weights, objective, iterations, converged).
    """
def simplex_volumes(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    ...
def slice(manifold: Complex, axis: typing.SupportsInt | typing.SupportsIndex, value: typing.SupportsFloat | typing.SupportsIndex) -> Slice:
    """
    One slice without an index or cached normals (tests every simplex).
    """
def smooth_slice(slice: Slice, levels: typing.SupportsInt | typing.SupportsIndex, crease_angle: typing.SupportsFloat | typing.SupportsIndex = 30.0, limit: bool = True) -> Slice:
    """
    A frame refined with Loop subdivision (OpenSubdiv), or B-spline curves for 2D animations; face_simplex inherited.
    """
def solid_measure(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> float:
    """
    Volume (3D) or area (2D) enclosed by a closed outward boundary.
    """
def stitch(frames: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], times: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], vertex_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"]] = {}, face_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"]] = {}, vertex_order: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, 1]"] = ...) -> Complex:
    """
    Keyframes ((m*k) by d, keyframe-major) with shared faces → animation manifold (a Complex).
    """
def subdivide_frame(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], levels: typing.SupportsInt | typing.SupportsIndex = 1, scheme: str = 'loop', crease_angle: typing.SupportsFloat | typing.SupportsIndex = 30.0, crease_edges: typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"] | None = None, limit: bool = True, vertex_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"]] = {}, face_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"]] = {}) -> dict:
    """
    OpenSubdiv refinement of a triangle/quad mesh with creases at sharp edges: dict of arrays.
    """
def subdivide_manifold(manifold: Complex, levels: typing.SupportsInt | typing.SupportsIndex = 1, scheme: str = 'schaefer', keep_keyframe_times: bool = False, keyframe_times: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex] = []) -> dict:
    """
    Schaefer et al. 2004 subdivision of a tet (or triangle) manifold: dict with 'manifold' (Complex), 'vertex_parents' (#V' by 2), 'simplex_parent' (#S'), 'keyframe_times'.
    """
def subdivide_polyline(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], segments: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], levels: typing.SupportsInt | typing.SupportsIndex = 1, crease_angle: typing.SupportsFloat | typing.SupportsIndex = 30.0, limit: bool = True, vertex_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"]] = {}, segment_attributes: collections.abc.Mapping[str, typing.Annotated[numpy.typing.ArrayLike, numpy.int32, "[m, n]"]] = {}) -> dict:
    """
    Cubic B-spline subdivision of polylines with corners at sharp turns (frames of 2D animations).
    """
def subtract_solid(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], hole_vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], hole_faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"], bool]:
    """
    (vertices, faces, unchanged) of frame \\ H; `unchanged` is True when H cannot touch the frame (the arrays are then a copy of the frame's).
    """
def vertex_normals(points: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], simplices: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
    ...
def voronoi_skeleton(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], internal: bool = True, external: bool = True, max_iterations: typing.SupportsInt | typing.SupportsIndex = 4, wrap: str = 'box', wrap_density: typing.SupportsInt | typing.SupportsIndex = 4, wrap_margin: typing.SupportsFloat | typing.SupportsIndex = 1.0, dihedral_limit: typing.SupportsFloat | typing.SupportsIndex = 0.7853981633974483, attach: bool = False, neighbourhood: typing.SupportsInt | typing.SupportsIndex = 2, in_plane_angle: typing.SupportsFloat | typing.SupportsIndex = 0.3) -> VoronoiSkeleton:
    ...
def wedge(vectors: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"]) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    ...
def wrap(vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"], shape: str = 'box', density: typing.SupportsInt | typing.SupportsIndex = 4, margin: typing.SupportsFloat | typing.SupportsIndex = 1.0) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]"], int, int]:
    ...
def write_mesh(path: str, vertices: typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]", "flags.c_contiguous"], faces: typing.Annotated[numpy.typing.NDArray[numpy.int32], "[m, n]", "flags.c_contiguous"]) -> None:
    ...

"""Procedural meshes and keyframe animations: the built-in demo and benchmark inputs.

Everything here is whole-array numpy; the meshes are closed and outward
oriented, so stitched manifolds and their slices are closed too.
"""

from __future__ import annotations

import numpy as np

from .frame_smoothing import subdivide_frame
from ._core import InputError, MeshingError


def icosahedron() -> tuple[np.ndarray, np.ndarray]:
    """The regular icosahedron on the unit sphere: (12, 3) vertices, (20, 3) outward faces."""
    phi = (1.0 + 5.0**0.5) / 2.0
    vertices = np.array(
        [
            [-1, phi, 0], [1, phi, 0], [-1, -phi, 0], [1, -phi, 0],
            [0, -1, phi], [0, 1, phi], [0, -1, -phi], [0, 1, -phi],
            [phi, 0, -1], [phi, 0, 1], [-phi, 0, -1], [-phi, 0, 1],
        ],
        dtype=np.float64,
    )  # fmt: skip
    faces = np.array(
        [
            [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
            [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
            [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
            [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
        ],
        dtype=np.int32,
    )  # fmt: skip
    return vertices / np.linalg.norm(vertices, axis=1, keepdims=True), faces


def subdivide_midpoint(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One 1-to-4 midpoint subdivision: each triangle (a, b, c) becomes four.

    New vertices are the edge midpoints, appended after the old vertices in the
    order of their sorted edge keys, so the same connectivity always gives the
    same numbering (keyframes subdivided separately still correspond).
    Orientation is kept.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    # The three edges of every face, (a, b), (b, c), (c, a), as undirected keys.
    directed = np.stack([faces, np.roll(faces, -1, axis=1)], axis=-1).reshape(-1, 2)
    keys = np.sort(directed, axis=1)
    edges, edge_of = np.unique(keys, axis=0, return_inverse=True)
    midpoints = 0.5 * (vertices[edges[:, 0]] + vertices[edges[:, 1]])
    mid = (len(vertices) + edge_of.reshape(-1)).reshape(-1, 3)  # mid[:, 0] is the midpoint of (a, b)
    a, b, c = faces.T
    ab, bc, ca = mid.T
    children = np.concatenate(
        [
            np.stack([a, ab, ca], axis=1),
            np.stack([ab, b, bc], axis=1),
            np.stack([ca, bc, c], axis=1),
            np.stack([ab, bc, ca], axis=1),
        ]
    )
    return np.concatenate([vertices, midpoints]), children.astype(np.int32)


def icosphere(subdivisions: int) -> tuple[np.ndarray, np.ndarray]:
    """A unit sphere of 20·4^subdivisions faces (subdivided icosahedron, projected)."""
    if subdivisions < 0:
        raise InputError(f"subdivisions must be >= 0, got {subdivisions}")
    vertices, faces = icosahedron()
    for _ in range(subdivisions):
        vertices, faces = subdivide_midpoint(vertices, faces)
        vertices /= np.linalg.norm(vertices, axis=1, keepdims=True)
    return vertices, faces


# -- keyframe poses ------------------------------------------------------------
# A pose is (squash, twist, offset): vertical scale (volume kept by scaling
# x and y by 1/sqrt), twist angle in radians from bottom to top, translation.
# Times are deliberately non-uniform: a quick squash before the take-off, a
# slow hang at the top, a fast fall.
DEMO_POSES = (
    # time   squash  twist   offset (x, y, z)
    (0.00, 1.00, 0.0, (0.0, 0.0, 0.0)),
    (0.12, 0.55, 0.0, (0.0, 0.0, -0.45)),
    (0.30, 1.60, 0.9, (0.6, 0.0, 0.8)),
    (0.55, 1.00, 2.2, (1.5, 0.3, 1.6)),
    (0.80, 1.35, 0.4, (2.4, 0.2, 0.7)),
    (1.00, 0.70, 0.0, (3.0, 0.0, -0.3)),
)


def pose(vertices: np.ndarray, squash: float, twist: float, offset) -> np.ndarray:
    """`vertices` squashed along z (volume-preserving), twisted about z, then moved."""
    lateral = 1.0 / np.sqrt(squash)
    x, y, z = vertices[:, 0] * lateral, vertices[:, 1] * lateral, vertices[:, 2] * squash
    # The twist grows linearly with height, so the top turns by `twist` relative to the bottom.
    extent = max(float(np.ptp(z)), 1e-12)
    angle = twist * (z - z.min()) / extent
    cos, sin = np.cos(angle), np.sin(angle)
    posed = np.stack([cos * x - sin * y, sin * x + cos * y, z], axis=1)
    return posed + np.asarray(offset, dtype=np.float64)


def bump(vertices: np.ndarray, amplitude: float) -> np.ndarray:
    """A radial ripple (three lobes around z), so the twist is visible on a sphere."""
    azimuth = np.arctan2(vertices[:, 1], vertices[:, 0])
    radial = 1.0 + amplitude * np.cos(3.0 * azimuth) * (1.0 - vertices[:, 2] ** 2)
    return vertices * radial[:, None]


def demo_keyframes(subdivisions: int = 4) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The demo animation: (frames (m, k, 3), faces (l, 3), times (m,)).

    An icosphere with three lobes squashes, leaps with a stretch and a twist,
    travels along x and lands squashed — 6 keyframes at non-uniform times.
    subdivisions=4 gives 5,120 faces; 2 gives 320 (a fast variant for tests).
    """
    rest, faces = icosphere(subdivisions)
    lobed = bump(rest, 0.3)
    times = np.array([p[0] for p in DEMO_POSES])
    frames = np.stack([pose(lobed, squash, twist, offset) for _, squash, twist, offset in DEMO_POSES])
    return frames, faces, times


def wobble(vertices: np.ndarray, phase: float, amplitude: float) -> np.ndarray:
    """A smooth travelling-wave deformation of `vertices` at `phase` (radians).

    Used by the benchmark to animate a real mesh over many keyframes: every
    vertex moves by a sum of sines of its rest position, so neighbouring
    keyframes stay close and the mesh stays unfolded for small amplitudes.
    """
    centre = vertices.mean(axis=0)
    size = float(np.ptp(vertices, axis=0).max())
    p = (vertices - centre) / size
    displacement = np.stack(
        [
            np.sin(2 * np.pi * p[:, 1] + phase),
            np.sin(2 * np.pi * p[:, 2] + 1.3 * phase),
            np.sin(2 * np.pi * p[:, 0] + 0.7 * phase),
        ],
        axis=1,
    )
    return vertices + amplitude * size * displacement


def voxel_surface(filled: np.ndarray, size: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Boundary of a union of unit voxels (`filled`: a 3D bool array) as outward triangles.

    The caller keeps voxels from touching along an edge or a corner only (the
    surface would not be a manifold there)."""
    filled = np.pad(np.asarray(filled, bool), 1)
    ids: dict[tuple[int, int, int], int] = {}
    faces = []

    def vertex(p):
        return ids.setdefault(tuple(int(x) for x in p), len(ids))

    for axis in range(3):
        step = np.eye(3, dtype=int)[axis]
        u, w = np.eye(3, dtype=int)[(axis + 1) % 3], np.eye(3, dtype=int)[(axis + 2) % 3]
        for cell in np.argwhere(filled):
            for sign in (1, -1):
                if filled[tuple(cell + sign * step)]:
                    continue
                base = cell + (step if sign > 0 else 0)
                quad = [base, base + u, base + u + w, base + w]  # counter-clockwise seen from +axis
                if sign < 0:
                    quad = quad[::-1]
                q = [vertex(p) for p in quad]
                faces += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    v = np.array(sorted(ids, key=ids.get), float) * size
    return v, np.array(faces, np.int32)


def smooth_genus(holes: int, levels: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """A curved genus-`holes` model without flat sides: a (2·holes+1) x 3 x 2 voxel slab (voxels
    0.5 wide, so (holes+0.5) x 1.5 x 1) with `holes` square holes through it in a row,
    Loop-subdivided `levels` times onto its limit surface (OpenSubdiv, no creases), centred at the
    origin. levels=2 gives 32·(26·holes+22) triangles: 1,596 vertices and 3,200 triangles for
    3 holes, 1,182 / 2,368 for 2, 2,424 / 4,864 for 5. Genus-n morph and speed inputs."""
    holes = _count(holes, "holes")
    filled = np.ones((2 * holes + 1, 3, 2), bool)
    filled[1 : 2 * holes : 2, 1, :] = False
    v, f = voxel_surface(filled, 0.5)
    s = subdivide_frame(v - v.mean(0), f, levels=levels, crease_angle=180.0)
    return np.asarray(s.vertices, np.float64), np.asarray(s.faces, np.int32)


def smooth_genus3(levels: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """A curved genus-3 model without flat sides: a 7 x 3 x 2 voxel slab with three square holes
    through it (size 3.5 x 1.5 x 1), Loop-subdivided `levels` times onto its limit surface
    (OpenSubdiv, no creases). levels=2: 1,596 vertices, 3,200 triangles. The benchmark's stand-in
    when the shared genus-3 model (libigl's 3holes.off) is absent. Same as smooth_genus(3, levels)."""
    return smooth_genus(3, levels)


def _count(n, name: str, minimum: int = 0) -> int:
    """`n` as an int >= minimum (bools and fractions refused)."""
    if isinstance(n, bool) or int(n) != n or n < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}, got {n!r}")
    return int(n)


def _unpinch(plate: np.ndarray) -> np.ndarray:
    """A 2D bool mask with every 2 x 2 checkerboard (two cells meeting at a corner only) filled in,
    so its extrusion's voxel surface is a manifold."""
    plate = np.array(plate, bool)
    while True:
        a, b, c, d = plate[:-1, :-1], plate[1:, :-1], plate[:-1, 1:], plate[1:, 1:]
        i, j = np.nonzero((a & d & ~b & ~c) | (b & c & ~a & ~d))
        if not len(i):
            return plate
        plate[i, j] = plate[i + 1, j] = plate[i, j + 1] = plate[i + 1, j + 1] = True


def _genus(vertices: np.ndarray, faces: np.ndarray) -> int:
    """The genus of a closed connected triangle mesh from V - E + F = 2 - 2g (E = 3F/2)."""
    return (2 - (len(vertices) - len(faces) // 2)) // 2


def ring_of_holes(holes: int = 4, levels: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """A curved genus-`holes` wheel: a round rim, a hub and `holes` spokes, so the holes (the
    sectors between the spokes) sit around a ring. Every bar is about 2 voxels wide and 1 voxel
    (drawn 2 voxels) thick, so after `levels` Loop subdivisions (OpenSubdiv, no creases) nothing
    is flat. Voxels are 0.3 across (0.6 high): the default wheel is 4.2 wide and centred at the
    origin. Defaults: 5,242 vertices, 10,496 triangles, genus 4 (the ~5k-vertex genus-4 speed
    model); more than 7 holes widen the wheel to `holes` voxels in radius."""
    holes = _count(holes, "holes", 1)
    m = max(7, holes)  # radius in voxels; the grid is 2m x 2m with cell centres at half-integers
    x = np.arange(2 * m) - m + 0.5
    X, Y = np.meshgrid(x, x, indexing="ij")
    r2 = X**2 + Y**2
    angle = 2 * np.pi * np.arange(holes) / holes
    along = X[..., None] * np.cos(angle) + Y[..., None] * np.sin(angle)
    across = -X[..., None] * np.sin(angle) + Y[..., None] * np.cos(angle)
    spokes = ((along > 0) & (np.abs(across) < 1.0)).any(-1)  # two cells wide
    hub = max(2.0, 0.5 * holes)  # spokes meet on the hub, not in a fan of slivers
    plate = (r2 <= m**2) & ((r2 > (m - 1.5) ** 2) | (r2 <= hub**2) | spokes)
    v, f = voxel_surface(_unpinch(plate)[:, :, None])
    if _genus(v, f) != holes:  # a guard on the digitisation: checked for 1..32 holes
        raise MeshingError(f"the voxel wheel for {holes} holes came out genus {_genus(v, f)}")
    v = (v - v.mean(0)) * np.array([0.3, 0.3, 0.6])
    s = subdivide_frame(v, f, levels=levels, crease_angle=180.0)
    return np.asarray(s.vertices, np.float64), np.asarray(s.faces, np.int32)


def geodesic_sphere(frequency: int) -> tuple[np.ndarray, np.ndarray]:
    """A unit sphere of 20·frequency² outward faces and 10·frequency² + 2 vertices: every
    icosahedron face cut into a frequency x frequency triangular grid, projected. Unlike
    icosphere, any frequency (not only powers of 2) is possible."""
    n = _count(frequency, "frequency", 1)
    corners, ico = icosahedron()
    s, t = (a.ravel() for a in np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij"))
    keep = s + t <= n
    s, t = s[keep], t[keep]  # the grid points a + s/n (b - a) + t/n (c - a)
    local = np.full((n + 2, n + 2), -1)
    local[s, t] = np.arange(len(s))
    # Every grid point of every face as integer weights of the 12 corners; equal weights are
    # the same point, so shared edges and corners weld exactly.
    weights = np.zeros((len(ico), len(s), 12), np.int64)
    rows = np.arange(len(ico))[:, None]
    cols = np.arange(len(s))[None, :]
    weights[rows, cols, ico[:, :1]] += n - s - t
    weights[rows, cols, ico[:, 1:2]] += s
    weights[rows, cols, ico[:, 2:3]] += t
    unique, ids = np.unique(weights.reshape(-1, 12), axis=0, return_inverse=True)
    ids = ids.reshape(len(ico), len(s))
    # Two triangles per grid cell, (s,t)(s+1,t)(s,t+1) and (s+1,t)(s+1,t+1)(s,t+1): both turn
    # the same way as (a, b, c).
    us, ut = s[s + t < n], t[s + t < n]
    ds, dt = s[s + t < n - 1], t[s + t < n - 1]
    tri = np.concatenate(
        [
            np.stack([local[us, ut], local[us + 1, ut], local[us, ut + 1]], 1),
            np.stack([local[ds + 1, dt], local[ds + 1, dt + 1], local[ds, dt + 1]], 1),
        ]
    )
    faces = ids[:, tri].reshape(-1, 3)
    vertices = unique @ corners
    return vertices / np.linalg.norm(vertices, axis=1, keepdims=True), faces.astype(np.int32)


def blob(triangles: int = 10000, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A smooth genus-0 blob of about `triangles` faces (the nearest 20·n², within 10% from 2,000
    up; default: 9,680 faces, 4,842 vertices): a geodesic sphere stretched into an ellipsoid
    (semi-axes 1.25, 1, 0.85) and pushed in and out by five wide Gaussian bumps at random
    (`seed`) places. The displacement is radial with radius >= 0.25 everywhere, so the surface
    stays a star-shaped graph over the sphere: closed, outward and free of self-intersections."""
    n = max(1, round(float(np.sqrt(_count(triangles, "triangles", 1) / 20.0))))
    vertices, faces = geodesic_sphere(n)
    rng = np.random.default_rng(seed)
    centres = rng.normal(size=(5, 3))
    centres /= np.linalg.norm(centres, axis=1, keepdims=True)
    amplitudes = rng.uniform(-0.15, 0.35, 5)  # the dents sum to at most 0.75: the radius stays >= 0.25
    widths = rng.uniform(0.35, 0.6, 5)  # radians-ish: low frequency, a handful of bumps per sphere
    closeness = vertices @ centres.T  # cos of the angle to each bump centre
    radius = 1.0 + (amplitudes * np.exp((closeness - 1.0) / widths**2)).sum(1)
    return vertices * radius[:, None] * np.array([1.25, 1.0, 0.85]), faces


def thick_genus(holes: int = 3, triangles: int = 13000) -> tuple[np.ndarray, np.ndarray]:
    """A smooth genus-`holes` model of about `triangles` faces: the smooth_genus slab with each
    voxel split into k x k x k and Loop-subdivided L >= 1 times, (k, L) picked for the face count
    2·(26·holes+22)·k²·4^L nearest `triangles` (fewest splits on ties, so it stays as round as
    smooth_genus). Defaults: k=1, L=3: 6,396 vertices, 12,800 triangles, genus 3 (the ~13k-face
    genus-3 speed model). The same 3.5 x 1.5 x 1 size as smooth_genus(holes)."""
    holes, triangles = _count(holes, "holes"), _count(triangles, "triangles", 1)
    base = 2 * (26 * holes + 22)  # triangles of the unsubdivided slab
    options = [(k, level) for k in range(1, 9) for level in range(1, 7)]
    k, level = min(options, key=lambda o: (abs(np.log(base * o[0] ** 2 * 4 ** o[1] / triangles)), o))
    filled = np.ones((2 * holes + 1, 3, 2), bool)
    filled[1 : 2 * holes : 2, 1, :] = False
    filled = filled.repeat(k, 0).repeat(k, 1).repeat(k, 2)
    v, f = voxel_surface(filled, 0.5 / k)
    s = subdivide_frame(v - v.mean(0), f, levels=level, crease_angle=180.0)
    return np.asarray(s.vertices, np.float64), np.asarray(s.faces, np.int32)


def limbs(levels: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """A genus-0 animal with thin limbs: a 5 x 3 x 3 voxel body on four legs 5 voxels long and
    with a tail 6 voxels long, all limbs 1 voxel across, Loop-subdivided `levels` times
    (OpenSubdiv, no creases) so the limbs become thin round tubes. Voxels are 0.5 (about
    5.5 x 1.5 x 4 overall); the vertex mean is the origin. levels=2: 2,914 vertices,
    5,824 triangles. For thin parts (slicing, morphing and collision tolerances along narrow
    tubes)."""
    filled = np.zeros((11, 3, 8), bool)
    filled[0:5, :, 5:8] = True  # body
    filled[[0, 0, 4, 4], [0, 2, 0, 2], 0:5] = True  # legs under the body's four bottom corners
    filled[5:11, 1, 6] = True  # tail from the middle of the +x side
    v, f = voxel_surface(filled, 0.5)
    s = subdivide_frame(v - v.mean(0), f, levels=levels, crease_angle=180.0)
    return np.asarray(s.vertices, np.float64), np.asarray(s.faces, np.int32)


def flat_box(holes: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A box with exactly flat sides, not subdivided: the voxel surface (0.5 voxels, quads split
    in two) of a solid (2·max(holes, 1)+1) x 3 x 2 voxel box with `holes` square through-holes in
    a row along x, as in smooth_genus, centred at the origin (coordinates are exact multiples of
    0.25). holes=0: a 1.5 x 1.5 x 1 box, 44 vertices, 84 triangles; holes=3: 96 / 200, genus 3.
    For flat-side cases (coplanar faces, exact ties)."""
    holes = _count(holes, "holes")
    filled = np.ones((2 * max(holes, 1) + 1, 3, 2), bool)
    filled[1 : 2 * holes : 2, 1, :] = False
    v, f = voxel_surface(filled, 0.5)
    return v - 0.5 * (v.min(0) + v.max(0)), f

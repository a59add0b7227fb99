"""Closed surfaces read from mesh files: checking, inside/outside and distances.

A :class:`ClosedSurface` is a watertight, consistently oriented boundary: triangles
in 3D (STL, OBJ, PLY, VTK/VTU, ... anything meshio reads; quads are split in two),
segments in 2D (line cells, the boundary of a flat triangulated area, or a polygon
given as its vertices). :func:`load_surface` refuses, naming the file and the
problem, a mesh that is not one: open edges (holes), edges shared by more than two
cells, cells that run a shared edge the same way (inconsistent orientation), or no
enclosed volume (area in 2D). A surface facing inwards is turned outwards.

The particle generators built on it are in :mod:`taisph.geometry.fill`
(``surface_points``, ``volume_points``, re-exported by :mod:`taisph.geometry`).
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..messages import InputError

PAIRS_PER_CHUNK = 2_000_000  # point-cell pairs handled at once by the O(points x cells) sums


class MeshError(InputError):
    """A mesh that cannot be used: unreadable, truncated, open, inconsistently oriented or
    empty (an :class:`taisph.messages.InputError`: one line naming the file and the
    problem; exit code 2 on the command line)."""


@dataclass(frozen=True)
class ClosedSurface:
    """A closed, outward-oriented surface: ``cells`` index ``vertices`` (``(V, dim)``);
    triangles ``(C, 3)`` in 3D, segments ``(C, 2)`` in 2D. ``name`` says where it came
    from (the file name) for messages."""

    dim: int
    vertices: np.ndarray
    cells: np.ndarray
    name: str = "<mesh>"

    @property
    def corners(self) -> np.ndarray:
        """The coordinates of each cell's vertices: ``(C, 3, 3)`` triangles, ``(C, 2, 2)`` segments."""
        return self.vertices[self.cells]

    @property
    def measure(self) -> float:
        """Enclosed volume (3D) or area (2D), positive for an outward surface."""
        return float(np.sum(_signed_measures(self.corners)))

    @property
    def area(self) -> float:
        """Surface area (3D) or perimeter (2D)."""
        c = self.corners
        if self.dim == 2:
            return float(np.sum(np.linalg.norm(c[:, 1] - c[:, 0], axis=1)))
        return float(0.5 * np.sum(np.linalg.norm(np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), axis=1)))

    @property
    def bounds(self) -> tuple:
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def transformed(self, scale=1.0, translate=None) -> "ClosedSurface":
        """The surface scaled about the origin by `scale` (> 0), then moved by `translate`."""
        shift = np.zeros(self.dim) if translate is None else np.asarray(translate, float)
        return ClosedSurface(self.dim, self.vertices * float(scale) + shift, self.cells, self.name)


def _signed_measures(corners: np.ndarray) -> np.ndarray:
    """Per cell: a0 x a1 / 2 (2D, shoelace) or a0 . (a1 x a2) / 6 (3D, divergence theorem)."""
    if corners.shape[2] == 2:
        a, b = corners[:, 0], corners[:, 1]
        return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    return np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])) / 6.0


def load_surface(source, dim: int | None = None, name: str | None = None) -> ClosedSurface:
    """A checked :class:`ClosedSurface` from `source`: a file path (read with meshio),
    a ``meshio.Mesh``, a ``(vertices, cells)`` pair, a ``(N, 2)`` array of polygon
    vertices (closed: the last joins the first), or a ClosedSurface (returned as is).

    `dim` (2 or 3) says which is expected; by default a mesh whose points all have
    the same z (or only x, y) is 2D and its line cells (or, without any, the boundary
    edges of its triangles and quads) are the polygon. STL files store float32
    coordinates; ASCII STL values are rounded to float32 as the format defines, so
    ASCII and binary copies of a mesh give the same points.
    """
    if isinstance(source, ClosedSurface):
        if dim is not None and source.dim != dim:
            raise MeshError(f"{source.name}: a {source.dim}D surface where a {dim}D one is needed")
        return source
    points, blocks, name = _read(source, name)
    if points.ndim != 2 or len(points) == 0 or points.shape[1] not in (2, 3):
        raise MeshError(f"{name}: the mesh has no points" if points.size == 0 else
                        f"{name}: points must be 2D or 3D coordinates, got an array of shape {points.shape}")
    if not np.all(np.isfinite(points)):
        raise MeshError(f"{name}: {np.count_nonzero(~np.all(np.isfinite(points), axis=1))} points have "
                        "coordinates that are not finite numbers (nan or inf)")
    for kind, data in blocks:  # a cell naming a point the file does not have (OBJ faces count from 1)
        if data.size and (data.min() < 0 or data.max() >= len(points)):
            bad = data.max() if data.max() >= len(points) else data.min()
            raise MeshError(f"{name}: a {kind} cell names point {int(bad)} (counted from 0), but the mesh has "
                            f"{len(points)} points")
    if points.shape[1] == 3 and points.shape[0] and np.ptp(points[:, 2]) == 0.0 and dim != 3:
        points = points[:, :2]
    mesh_dim = dim or (2 if points.shape[1] == 2 else 3)
    if mesh_dim == 3 and points.shape[1] != 3:
        raise MeshError(f"{name}: the mesh is flat (2D) but a 3D surface is needed")
    if mesh_dim == 2 and points.shape[1] != 2:
        raise MeshError(f"{name}: a 2D outline must lie in a plane z = const; its z spans "
                        f"{points[:, 2].min():g} .. {points[:, 2].max():g}")
    cells = _cells(blocks, mesh_dim, name)
    vertices, inverse = np.unique(points, axis=0, return_inverse=True)  # merge repeated points
    cells = inverse.reshape(-1)[cells]
    distinct = np.all(np.diff(np.sort(cells, axis=1), axis=1) > 0, axis=1)
    cells = cells[distinct]  # cells with a repeated vertex (collapsed) have no extent
    if len(cells) == 0:
        raise MeshError(f"{name}: the mesh has no {'triangles' if mesh_dim == 3 else 'segments'} of nonzero size")
    _check_closed(cells, len(vertices), name)
    signed = float(np.sum(_signed_measures(vertices[cells])))
    extent = float(np.max(np.ptp(vertices, axis=0)))
    if not abs(signed) > 1e-9 * extent**mesh_dim:
        what = "volume" if mesh_dim == 3 else "area"
        raise MeshError(f"{name}: the surface encloses no {what} ({what} {signed:.3g}, extent {extent:.3g})")
    if signed < 0:  # facing inwards: turn outwards
        cells = cells[:, ::-1]
    return ClosedSurface(mesh_dim, vertices, np.ascontiguousarray(cells), name)


def _read(source, name):
    """(points (N, 2|3) float64, [(cell type, (C, k) int)], name) from any accepted source."""
    import meshio

    if isinstance(source, (str, Path)):
        path = Path(source)
        name = name or str(source)
        if not path.is_file():
            raise MeshError(f"{name}: no such mesh file")
        if path.suffix.lower() == ".stl":
            check_stl(path, name)  # a truncated file, named as such (meshio's own errors do not say)
        try:
            with warnings.catch_warnings():  # meshio's binary-STL size test overflows on ASCII files
                warnings.filterwarnings("ignore", "overflow encountered", RuntimeWarning)
                mesh = meshio.read(path)
        except Exception as err:  # meshio raises many kinds (ReadError, ValueError, KeyError...)
            raise MeshError(f"{name}: cannot read it as a mesh ({type(err).__name__}: {err})") from None
        points = np.asarray(mesh.points, float)
        if path.suffix.lower() == ".stl":  # the format's precision (see load_surface)
            points = points.astype(np.float32).astype(float)
        return points, [(b.type, np.asarray(b.data)) for b in mesh.cells], name
    if isinstance(source, meshio.Mesh):
        return np.asarray(source.points, float), [(b.type, np.asarray(b.data)) for b in source.cells], name or "<mesh>"
    if isinstance(source, tuple) and len(source) == 2:
        points, cells = (np.asarray(a) for a in source)
        kind = {2: "line", 3: "triangle", 4: "quad"}.get(cells.shape[1] if cells.ndim == 2 else 0)
        if kind is None:
            raise MeshError(f"{name or '<mesh>'}: cells must be an (C, 2|3|4) array, got shape {cells.shape}")
        return points.astype(float), [(kind, cells)], name or "<mesh>"
    points = np.asarray(source, float)
    if points.ndim != 2 or points.shape[1] != 2 or len(points) < 3:
        raise MeshError(f"{name or '<polygon>'}: a polygon needs an (N >= 3, 2) array of vertices, "
                        f"got shape {points.shape}")
    if np.array_equal(points[0], points[-1]):
        points = points[:-1]
    k = np.arange(len(points))
    return points, [("line", np.column_stack([k, np.roll(k, -1)]))], name or "<polygon>"


STL_HEADER, STL_TRIANGLE = 84, 50  # a binary STL: 80 bytes, a uint32 count, then 50 bytes per triangle
STL_FACET = ("facet normal", "outer loop", "vertex", "vertex", "vertex", "endloop", "endfacet")  # an ASCII facet


def check_stl(path, name=None) -> None:
    """Raise :class:`MeshError` (one line: the file and what is wrong) if the STL file
    `path` is cut short or malformed: a binary file whose length is not its 84-byte
    header's triangle count times 50 bytes, an ASCII file that ends inside a facet or
    lacks ``endsolid``, or a line out of a facet's order."""
    path = Path(path)
    name = name or str(path)
    data = path.read_bytes()
    size = len(data)
    count = int.from_bytes(data[80:84], "little") if size >= STL_HEADER else None
    if count is not None and size == STL_HEADER + STL_TRIANGLE * count:
        return  # binary, whole (even if its header starts with "solid")
    text = data.decode("latin-1")
    if re.search(r"[^\x20-\x7e\r\n\t]", text) is None and "\n" in text:  # lines of text, not a binary header
        if text.lstrip()[:5].lower() == "solid":
            return _check_ascii_stl(text.splitlines(), name)
        raise MeshError(f"{name}: cannot read it as a mesh: a text file, but an ASCII STL starts with 'solid' "
                        f"(got {text.strip()[:40]!r})")
    if count is None:
        raise MeshError(f"{name}: truncated: {size} bytes, shorter than the {STL_HEADER}-byte header of a binary STL")
    whole, rest = divmod(size - STL_HEADER, STL_TRIANGLE)
    if size < STL_HEADER + STL_TRIANGLE * count:
        raise MeshError(f"{name}: truncated: the {STL_HEADER}-byte header says {count} triangles, the file has "
                        f"{whole}" + (f" and {rest} bytes of another" if rest else "")
                        + f" ({size} bytes of {STL_HEADER + STL_TRIANGLE * count})")
    raise MeshError(f"{name}: the {STL_HEADER}-byte header says {count} triangles ({STL_HEADER + STL_TRIANGLE * count}"
                    f" bytes), but the file has {size} bytes: not a binary STL, or a corrupt one")


def _check_ascii_stl(lines, name) -> None:
    """An ASCII STL's lines: ``solid``, facets of :data:`STL_FACET` (a vertex with three
    numbers), ``endsolid``; :class:`MeshError` naming the line and the facet otherwise."""
    state, facets, number = None, 0, 0  # state: index into STL_FACET of the next line, None outside a solid
    last = max((k for k, line in enumerate(lines, 1) if line.strip()), default=0)
    for number, line in enumerate(lines, 1):
        words = line.split()
        if not words:
            continue
        key = " ".join(words[:2] if words[0].lower() in ("facet", "outer") else words[:1]).lower()
        if state is not None and state == 0 and key == "endsolid":
            state = None
            continue
        problem = (("" if key == "solid" else "expected 'solid' (an ASCII STL)") if state is None else
                   f"expected '{STL_FACET[state]}'" + (" or 'endsolid'" if state == 0 else "")
                   if key != STL_FACET[state] else
                   "" if key != "vertex" or _three_numbers(words[1:]) else "a vertex needs three numbers")
        if problem and number == last:  # the last line, cut short
            state = state or -1  # inside a facet
            break
        if problem:
            raise MeshError(f"{name}: line {number} (facet {facets + 1}): {problem}, got {line.strip()[:40]!r}")
        state = 0 if state is None else (state + 1) % len(STL_FACET)
        facets += state == 0 and key == "endfacet"
    else:
        if state is None:
            return
    whole = f"{facets} whole facet{'s' * (facets != 1)}"
    where = f"inside facet {facets + 1}" if state else f"after facet {facets} without 'endsolid'"
    end = f"line {last}: {lines[last - 1].strip()[:40]!r}; " if last else ""
    raise MeshError(f"{name}: truncated: the file ends {where} ({end}{whole})")


def _three_numbers(words) -> bool:
    try:
        return len(words) == 3 and all(np.isfinite(float(w)) for w in words)
    except ValueError:
        return False


def _cells(blocks, dim, name) -> np.ndarray:
    """The triangles (3D) or segments (2D) of the mesh's cell blocks."""
    if dim == 3:
        tris = [d for t, d in blocks if t == "triangle"]
        quads = [d for t, d in blocks if t == "quad"]
        tris += [d[:, [0, 1, 2]] for d in quads] + [d[:, [0, 2, 3]] for d in quads]
        if not tris:
            raise MeshError(f"{name}: no triangle or quad cells (cell types: "
                            f"{', '.join(sorted({t for t, _ in blocks})) or 'none'})")
        return np.concatenate(tris).astype(np.int64)
    lines = [d for t, d in blocks if t == "line"]
    if lines:
        return np.concatenate(lines).astype(np.int64)
    faces = [d for t, d in blocks if t in ("triangle", "quad")]
    if not faces:
        raise MeshError(f"{name}: no line, triangle or quad cells to take a 2D outline from")
    edges = np.concatenate([np.stack([f, np.roll(f, -1, axis=1)], axis=2).reshape(-1, 2) for f in faces])
    keys, first, counts = np.unique(np.sort(edges, axis=1), axis=0, return_index=True, return_counts=True)
    return edges[first[counts == 1]].astype(np.int64)  # the boundary: edges of one face only


def _check_closed(cells, n_vertices, name):
    """Raise MeshError listing every way in which `cells` fail to bound a volume (area).

    3D: every undirected edge must belong to exactly two triangles, which run it in
    opposite directions. 2D: every vertex must start one segment and end one."""
    problems = []
    if cells.shape[1] == 3:
        directed = np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]], cells[:, [2, 0]]])
        _, counts = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
        _, same_way = np.unique(directed, axis=0, return_counts=True)
        if np.any(counts == 1):
            problems.append(f"{np.count_nonzero(counts == 1)} open edges (holes: edges of only one triangle)")
        if np.any(counts > 2):
            problems.append(f"{np.count_nonzero(counts > 2)} edges shared by more than two triangles")
        if np.any(same_way > 1):
            problems.append(f"inconsistent orientation: {np.count_nonzero(same_way > 1)} edges run the same way "
                            "by both their triangles (some triangles face the other way)")
    else:
        starts = np.bincount(cells[:, 0], minlength=n_vertices)
        ends = np.bincount(cells[:, 1], minlength=n_vertices)
        degree = starts + ends
        if np.any(degree == 1):
            problems.append(f"{np.count_nonzero(degree == 1)} open ends (vertices of only one segment)")
        if np.any(degree > 2):
            problems.append(f"{np.count_nonzero(degree > 2)} vertices shared by more than two segments")
        wrong = (degree == 2) & (starts != 1)
        if np.any(wrong):
            problems.append(f"inconsistent orientation: {np.count_nonzero(wrong)} vertices start (or end) "
                            "both their segments")
    if problems:
        raise MeshError(f"{name}: not a closed surface: " + "; ".join(problems))


def winding_number(surface: ClosedSurface, points) -> np.ndarray:
    """The generalised winding number of `surface` around each point: 1 inside, 0
    outside (cavities 0), fractional only near the surface.

    3D: the sum of the triangles' signed solid angles over 4 pi, each from
    tan(Omega/2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|) with
    a, b, c the vertices relative to the point (Van Oosterom & Strackee 1983, IEEE
    Trans. Biomed. Eng. 30:125; Jacobson et al. 2013, ACM TOG 32:33). 2D: the sum of
    the segments' signed angles over 2 pi. O(points x cells): for checks and small
    meshes; :func:`taisph.geometry.fill.volume_points` fills lattices in O(points).
    """
    points = np.asarray(points, float).reshape(-1, surface.dim)
    corners = surface.corners
    out = np.empty(len(points))
    step = max(1, PAIRS_PER_CHUNK // len(corners))
    for s in range(0, len(points), step):
        rel = corners[None, :, :, :] - points[s:s + step, None, None, :]
        if surface.dim == 2:
            a, b = rel[:, :, 0], rel[:, :, 1]
            angle = np.arctan2(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0], np.einsum("...i,...i", a, b))
            out[s:s + step] = angle.sum(axis=1) / (2 * np.pi)
            continue
        a, b, c = rel[:, :, 0], rel[:, :, 1], rel[:, :, 2]
        la, lb, lc = (np.linalg.norm(v, axis=-1) for v in (a, b, c))
        num = np.einsum("...i,...i", a, np.cross(b, c))
        den = la * lb * lc + np.einsum("...i,...i", a, b) * lc + np.einsum("...i,...i", b, c) * la \
            + np.einsum("...i,...i", c, a) * lb
        out[s:s + step] = 2.0 * np.arctan2(num, den).sum(axis=1) / (4 * np.pi)
    return out


def contains(surface: ClosedSurface, points) -> np.ndarray:
    """Mask of the points inside `surface` (winding number above one half)."""
    return winding_number(surface, points) > 0.5


def pair_distances(points: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Distance from each point ``(P, dim)`` to its cell ``(P, dim, dim)`` (a triangle
    in 3D, a segment in 2D), pair by pair.

    Triangle: if the point's projection on the plane falls inside (the three edge
    normals agree), the distance to the plane, else the distance to the nearest
    edge (Ericson 2005, Real-Time Collision Detection, sec. 5.1.5, by regions)."""
    if corners.shape[1] == 2:
        return _segment_distance(points, corners[:, 0], corners[:, 1])
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    n = np.cross(b - a, c - a)
    nn = np.einsum("ij,ij->i", n, n)
    inside = np.ones(len(points), bool)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("ij,ij->i", np.cross(v - u, points - u), n) >= 0.0
    plane = np.abs(np.einsum("ij,ij->i", points - a, n)) / np.sqrt(np.where(nn > 0, nn, 1.0))
    edges = np.minimum(np.minimum(_segment_distance(points, a, b), _segment_distance(points, b, c)),
                       _segment_distance(points, c, a))
    return np.where(inside & (nn > 0), plane, edges)


def _segment_distance(p, a, b):
    d = b - a
    dd = np.einsum("ij,ij->i", d, d)
    t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * d), axis=1)


def distance_to_surface(surface: ClosedSurface, points) -> np.ndarray:
    """Unsigned distance from each point to the nearest cell of `surface`
    (O(points x cells), chunked)."""
    points = np.asarray(points, float).reshape(-1, surface.dim)
    corners = surface.corners
    out = np.empty(len(points))
    step = max(1, PAIRS_PER_CHUNK // len(corners))
    for s in range(0, len(points), step):
        p = points[s:s + step]
        d = pair_distances(np.repeat(p, len(corners), axis=0), np.tile(corners, (len(p), 1, 1)))
        out[s:s + step] = d.reshape(len(p), len(corners)).min(axis=1)
    return out


# --- meshes to try things with -------------------------------------------------------
def icosphere(radius=1.0, subdivisions=3, centre=(0.0, 0.0, 0.0)) -> tuple:
    """Vertices and outward triangles of an icosahedron subdivided `subdivisions`
    times, vertices pushed to the sphere (20 * 4**subdivisions triangles)."""
    t = (1 + 5**0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
         (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    v = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        middle = {}

        def mid(i, j):
            key = (min(i, j), max(i, j))
            if key not in middle:
                m = v[i] + v[j]
                v.append(m / np.linalg.norm(m))
                middle[key] = len(v) - 1
            return middle[key]

        f = [tri for a, b, c in f for tri in
             ((a, mid(a, b), mid(c, a)), (b, mid(b, c), mid(a, b)), (c, mid(c, a), mid(b, c)),
              (mid(a, b), mid(b, c), mid(c, a)))]
    return radius * np.array(v) + np.asarray(centre), np.array(f)


def box_mesh(lo, hi) -> tuple:
    """Vertices and the 12 outward triangles of the box [lo, hi]."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    v = np.array([[(lo, hi)[(k >> a) & 1][a] for a in range(3)] for k in range(8)])
    f = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4), (2, 6, 7), (2, 7, 3),
         (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
    return v, np.array(f)


def sliver_box(lo, hi, n=80) -> tuple:
    """Vertices and outward triangles of the box [lo, hi] as a CAD export may tessellate
    it: its four faces along x cut into n strips at x_k = lo + (hi - lo) (k/n)^1.5
    (uneven), each strip two long thin triangles (aspect up to about n); the two end
    faces two triangles each. The same box as :func:`box_mesh`, 8n + 4 triangles."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    x = lo[0] + (hi[0] - lo[0]) * (np.arange(n + 1) / n) ** 1.5
    ring = [(lo[1], lo[2]), (hi[1], lo[2]), (hi[1], hi[2]), (lo[1], hi[2])]  # around x
    vertices = np.array([[xk, y, z] for xk in x for y, z in ring])
    faces = []
    for k in range(n):
        for j in range(4):
            a, b = 4 * k + j, 4 * k + (j + 1) % 4
            faces += [(a, a + 4, b + 4), (a, b + 4, b)]
    faces += [(0, 2, 1), (0, 3, 2), (4 * n, 4 * n + 1, 4 * n + 2), (4 * n, 4 * n + 2, 4 * n + 3)]
    faces = np.array(faces)
    corners = vertices[faces]  # turn every triangle outwards (the box is convex)
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    outward = np.einsum("ij,ij->i", normal, corners.mean(axis=1) - (lo + hi) / 2) > 0
    return vertices, np.where(outward[:, None], faces, faces[:, ::-1])

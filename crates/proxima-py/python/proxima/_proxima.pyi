"""Type stubs of proxima's native module (the API contract of the package)."""

from os import PathLike
from typing import Iterator, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

Primitives = Literal["vertices", "edges", "faces", "polygons"]
FloatArray = npt.NDArray[np.floating]
Faces = Union[npt.ArrayLike, Sequence[Sequence[int]]]

__version__: str

def load(path: Union[str, PathLike[str]]) -> Mesh:
    """Reads a mesh file: OBJ, PLY (ASCII or binary), STL (ASCII or binary),
    OFF, binary glTF (``.glb``: the triangles of its scene, node transforms
    applied), each optionally gzip-compressed (``.gz``), as the command line
    does.

    Raises ``OSError`` when the file cannot be read and ``ValueError`` when
    its content is malformed or holds no vertex; the message names the file
    (and the line where it can), as the command line's.

    >>> mesh = proxima.load("bunny.obj")
    """

def noisy_icosphere(frequency: int, seed: int = 1) -> Mesh:
    """A closed sphere of radius about 1 with smooth noise: ``20 * frequency**2``
    triangles (``noisy_icosphere(224)`` is the benchmarks' 1M-triangle ``ico1m``).

    >>> proxima.noisy_icosphere(4).faces.shape
    (320, 3)
    """

def memory_budget() -> int:
    """The memory budget in bytes that every size is checked against before
    anything is allocated: ``PROXIMA_MEMORY_BUDGET`` (bytes, or with a K, M
    or G suffix: ``"512M"``) or the default, three quarters of the available
    memory and at most 2 GiB. ``ValueError`` when the variable is malformed.

    >>> import os, proxima
    >>> os.environ["PROXIMA_MEMORY_BUDGET"] = "512M"
    >>> proxima.memory_budget()
    536870912
    """

def max_threads() -> int:
    """The largest ``threads=`` a batch call accepts: 4 per core, at least 8
    (the command line's ``--threads`` cap: one policy, the library's)."""

def check_fits(option: str, value: object, count: int, bytes_each: int) -> None:
    """The library's memory check, as every call of the package makes it
    before allocating: raises ``ValueError`` unless ``count`` items of
    ``bytes_each`` bytes fit the memory budget (:func:`memory_budget`). The
    message starts with ``option`` and ``value``, gives the bytes needed and
    the budget, and says to set ``PROXIMA_MEMORY_BUDGET`` to change it
    (``"grid 512: needs about 1.0 GiB (134217728 × 8 = 1073741824 bytes),
    more than the memory budget of 512.0 MiB (536870912 bytes; set
    PROXIMA_MEMORY_BUDGET to change it)"``); a malformed variable is a
    ``ValueError`` naming it.

    >>> proxima.check_fits("n", 1000, 1000, 12)
    """

def training_sample_counts(total: int, uniform_fraction: float) -> Tuple[int, int]:
    """``(near, uniform)``: how many of ``total`` training samples
    :meth:`Mesh.training_samples` draws near the surface and uniform in its
    box when ``uniform_fraction`` (in [0, 1], else ``ValueError``) of them
    are uniform: ``uniform`` the nearest whole number to
    ``total * uniform_fraction``, halves rounded down.

    >>> proxima.training_sample_counts(101, 0.5)
    (51, 50)
    """

def mesh_suffixes() -> list[str]:
    """The suffixes of the files :func:`load` reads, each also with ``.gz``
    after it: ``[".obj", ".ply", ".stl", ".off", ".glb"]`` (the library's
    formats)."""

def traverse(
    origin: npt.ArrayLike,
    direction: npt.ArrayLike,
    cell_size: Union[float, npt.ArrayLike],
    steps: int,
) -> Tuple[npt.NDArray[np.int64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The first ``steps`` cells that the ray ``origin + t * direction``
    (t >= 0) crosses in a grid of cells of ``cell_size`` (one number, or three)
    with a corner at the origin (Amanatides & Woo): ``(cells (n, 3) int64,
    t_enter (n,), t_exit (n,))``, in the ray's parameter (units of
    ``direction``'s length).

    >>> cells, t0, t1 = proxima.traverse([0.5, 0.5, 0.5], [1, 0, 0], 1.0, 3)
    >>> cells.tolist()
    [[0, 0, 0], [1, 0, 0], [2, 0, 0]]
    """

Pose = npt.ArrayLike
"""A rigid pose: a (4, 4) matrix ``[R t; 0 0 0 1]`` (row-major, as numpy
writes it; float64 or float32), ``R`` a rotation (``R^T R`` within 1e-6 of
the identity, determinant > 0), finite, translation within +-1e38. Anything
else is a ``ValueError`` naming the argument (``pose_b: the pose is not a
rotation: ...``; ``pose_b[3]: ...`` for one pose of a stack)."""

class Answers:
    """The arrays of a query asked for more than its plain answer (a
    ``return_*`` option): by name as attributes or items, in :meth:`keys`
    order, and unpacking as the plain tuple (``closest, distance, index =
    mesh.closest_points(p, return_normal=True)``). Only the arrays asked for
    are there; the others raise ``AttributeError``. A query without an
    answer (a ray that misses) has -1 and NaN in its rows.

    >>> a = mesh.closest_points(points, return_barycentric=True, return_feature=True)
    >>> a.barycentric.shape, a.feature[:3]
    """

    closest: npt.NDArray[np.float64]
    """``closest_points``: the closest points, (N, 3)."""
    distance: npt.NDArray[np.float64]
    """``closest_points``: the distances, (N,)."""
    t: npt.NDArray[np.float64]
    """``cast_rays``: the hit distances, (N,), ``inf`` for a miss."""
    index: npt.NDArray[np.int64]
    """The face of each answer, (N,)."""
    triangle: npt.NDArray[np.int64]
    """``return_barycentric``: the fan triangle (v0, vi, vi+1) of the face that
    holds the point, numbered over all faces' fans in order, (N,)."""
    corners: npt.NDArray[np.int64]
    """``return_barycentric``: that triangle's vertices, (N, 3)."""
    barycentric: npt.NDArray[np.float64]
    """``return_barycentric``: the point's weights of ``corners``, (N, 3):
    non-negative, summing to 1; for closest points, located again in float64
    on the answer's triangle (they reproduce ``closest`` within 1e-6 of the
    diagonal); for rays, the ray test's own."""
    feature: npt.NDArray[np.int8]
    """``return_feature``: the smallest mesh feature holding the point, (N,):
    0 the inside of a face (a polygon's fan diagonals included), 1 an edge,
    2 a vertex."""
    feature_vertices: npt.NDArray[np.int64]
    """``return_feature``: the feature's vertices, (N, 2): the edge's two (in
    the face's order), the vertex and -1, or -1, -1 for a face."""
    normal: npt.NDArray[np.float64]
    """``return_normal``: the shading normal, unit length, (N, 3): the file's
    per-corner normals (:attr:`Mesh.corner_normals`) when it had them, else
    the vertex normals (:attr:`Mesh.vertex_normals`), interpolated by the
    barycentric weights."""
    uv: npt.NDArray[np.float64]
    """``return_uv``: the texture coordinates (:attr:`Mesh.corner_uvs`)
    interpolated by the barycentric weights, (N, 2); ``ValueError`` naming
    ``return_uv`` on a mesh without them."""
    face_normal: npt.NDArray[np.float64]
    """``return_normal``: the triangle's unit normal (right-handed in the
    face's order), (N, 3)."""
    def keys(self) -> list[str]:
        """The names of the arrays, in order."""
    def __getitem__(self, name: str) -> npt.NDArray[np.generic]: ...
    def __iter__(self) -> Iterator[npt.NDArray[np.generic]]: ...
    def __len__(self) -> int: ...

class PairDistance:
    """The nearest points of two placed meshes (:func:`distance`); unpacks
    as ``(distance, point_a, point_b, face_a, face_b)``."""

    @property
    def distance(self) -> float:
        """The distance between the meshes (0 when their surfaces meet)."""
    @property
    def point_a(self) -> npt.NDArray[np.float64]:
        """The point on the first mesh, in the world, shape (3,)."""
    @property
    def point_b(self) -> npt.NDArray[np.float64]:
        """The point on the second mesh, in the world, shape (3,)."""
    @property
    def face_a(self) -> int:
        """The face of the first mesh holding ``point_a``."""
    @property
    def face_b(self) -> int:
        """The face of the second mesh holding ``point_b``."""
    @property
    def triangle_a(self) -> int:
        """The triangle (fan triangles of the faces, in order) holding ``point_a``."""
    @property
    def triangle_b(self) -> int:
        """The triangle of the second mesh holding ``point_b``."""
    @property
    def barycentric_a(self) -> npt.NDArray[np.float64]:
        """``point_a`` in barycentric coordinates of ``triangle_a``'s corners, shape (3,)."""
    @property
    def barycentric_b(self) -> npt.NDArray[np.float64]:
        """``point_b`` in barycentric coordinates of ``triangle_b``'s corners, shape (3,)."""
    def __iter__(self) -> Iterator[object]: ...
    def __len__(self) -> int: ...

class Hausdorff:
    """The Hausdorff distance between two meshes' surfaces
    (:func:`hausdorff` of two :class:`Mesh`): bounds that meet within the
    tolerance asked, and the pair of points that realizes the lower one.
    ``float(h)`` is the upper bound."""

    @property
    def lower(self) -> float:
        """A lower bound: the distance between ``point_a`` and ``point_b``."""
    @property
    def upper(self) -> float:
        """An upper bound: no point of either surface (of ``a`` only, when
        one-sided) lies farther from the other."""
    @property
    def point_a(self) -> npt.NDArray[np.float64]:
        """The point of ``a`` of the pair realizing ``lower``, shape (3,)."""
    @property
    def point_b(self) -> npt.NDArray[np.float64]:
        """The point of ``b`` of that pair, shape (3,)."""
    @property
    def face_a(self) -> int:
        """The face of ``a`` holding ``point_a``."""
    @property
    def face_b(self) -> int:
        """The face of ``b`` holding ``point_b``."""
    @property
    def from_a(self) -> bool:
        """Whether ``lower`` is measured from ``a``'s surface (``point_a`` is
        the far point, ``point_b`` its nearest on ``b``), else from ``b``'s."""
    def __float__(self) -> float: ...

@overload
def distance(
    a: Mesh,
    b: Mesh,
    pose_a: Optional[Pose] = None,
    pose_b: Optional[Pose] = None,
    *,
    max_distance: Optional[float] = None,
    threads: Optional[int] = None,
) -> Optional[PairDistance]:
    """The distance between mesh ``a`` placed by ``pose_a`` and mesh ``b``
    placed by ``pose_b`` (``None``: the identity): the smallest distance
    over all pairs of their triangles, in float64 (``proxima::pair``), and
    where it is reached, as a :class:`PairDistance`. With ``max_distance``,
    ``None`` when the distance is ``max_distance`` or more (found without
    opening farther parts of the meshes).

    ``pose_b`` of shape (P, 4, 4): ``b`` at each pose with ``a`` unmoved
    (``pose_a`` must be None or the identity, else ``ValueError``), as
    arrays ``(distance (P,), point_a (P, 3), point_b (P, 3), face_a (P,),
    face_b (P,))``; beyond ``max_distance``: ``inf``, NaN points, faces -1.
    The stack is counted against the memory budget before it is read.

    ``ValueError`` naming ``a`` or ``b`` (a mesh without faces),
    ``pose_a``/``pose_b`` (see :data:`Pose`), ``max_distance`` (negative or
    NaN) or ``threads``. The GIL is released during the walk.

    >>> square = proxima.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> T = np.eye(4); T[0, 3] = 3.0          # b moved 3 along x
    >>> d = proxima.distance(square, square, pose_b=T)
    >>> d.distance, d.point_a[0], d.point_b[0]
    (2.0, 1.0, 3.0)
    """

@overload
def distance(
    a: Mesh,
    b: Mesh,
    pose_a: None,
    pose_b: npt.ArrayLike,
    *,
    max_distance: Optional[float] = None,
    threads: Optional[int] = None,
) -> Tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.int64],
    npt.NDArray[np.int64],
]: ...

class VoxelGrid:
    """The cells of a cubic grid that a mesh's triangles overlap (exact test)."""

    @property
    def resolution(self) -> int:
        """Cells per side."""
    @property
    def origin(self) -> npt.NDArray[np.float64]:
        """The corner of cell (0, 0, 0), shape (3,)."""
    @property
    def cell_size(self) -> float:
        """The side of a cell."""
    @property
    def cells(self) -> npt.NDArray[np.int64]:
        """The occupied cells' indices, shape (M, 3), in increasing (i, j, k) order
        of the grid's storage (x fastest)."""
    def dense(self) -> npt.NDArray[np.bool_]:
        """A (N, N, N) bool array, ``dense()[i, j, k]`` true where cell (i, j, k)
        is occupied."""
    def __len__(self) -> int:
        """The number of occupied cells."""

class Mesh:
    """A polygon mesh and the structures that answer queries on it.

    The structures are built on first use and kept: the first
    ``closest_points`` on faces builds the faces' tree, later calls (and
    ``signed_distance``, which uses the same tree) reuse it.

    Every batch call takes ``threads``: ``None`` for rayon's pool of all
    cores, or ``k`` for k worker threads of its own (pools are kept per
    calling Python thread, so two Python threads each asking for one run
    side by side). The GIL is released while a call works.

    >>> import numpy as np, proxima
    >>> mesh = proxima.Mesh(np.eye(3), [[0, 1, 2]])
    >>> closest, distance, face = mesh.closest_points([[0, 0, 0]])
    >>> face.tolist()
    [0]
    """

    def __init__(self, vertices: npt.ArrayLike, faces: Faces) -> None:
        """A mesh from ``vertices`` (V, 3) float32 or float64 and ``faces``:
        an integer (F, 3) array (triangles), an integer (F, k) array, or a
        list of index sequences of any lengths >= 3 (polygons). Coordinates
        are stored as float32.

        Raises ``ValueError`` for a wrong shape or dtype, a coordinate that is
        NaN or infinite, an index out of range or a face of fewer than three
        vertices.
        """
    @staticmethod
    def from_trimesh(mesh: object) -> Mesh:
        """The mesh of a ``trimesh.Trimesh`` (its ``vertices`` and ``faces``)."""
    @property
    def vertices(self) -> npt.NDArray[np.float32]:
        """The vertices, (V, 3) float32 (a copy)."""
    @property
    def vertex_normals(self) -> npt.NDArray[np.float32]:
        """Every vertex's unit normal, (V, 3) float32: its faces' unit normals
        (fan triangles for polygons) weighted by their angles at the vertex,
        summed in float64; zero for a vertex no face uses. Computed once and
        kept (``"normals"`` in :meth:`built_structures`)."""
    def update_vertices(self, positions: npt.ArrayLike) -> list[tuple[str, bool, float]]:
        """Moves the vertices to ``positions`` ((V, 3), one row per vertex in
        the same order; the faces stay) and brings every structure built so
        far up to date: the trees are refit in place (the same shape, new
        boxes) or rebuilt where a refit has worn them past 1.5 times their
        surface-area cost at build; the signed-distance fields' expansions
        are refit over the faces' tree and their normals computed again; the
        sign certificate is made again once the signed distances asked
        since number half the triangles (until then the winding number is
        walked: the same signs). Structures not built yet stay so.
        The file's corner normals are dropped (they described the old
        surface); corner UVs stay.

        Every query afterwards answers exactly as a new ``Mesh`` over the
        moved vertices would; only the speed depends on refit or rebuild.
        Returns ``(structure, rebuilt, cost_ratio)`` per structure updated
        (``cost_ratio``: a tree's surface-area cost over its cost at build,
        NaN where it was not refit but rebuilt, 1 for the other structures).

        Raises ValueError naming ``positions`` for another vertex count, a
        NaN or infinite coordinate, or one beyond 2**60; the mesh and its
        structures are then unchanged. The GIL is released; a call while
        another thread queries the same mesh raises RuntimeError (the mesh
        is borrowed) rather than wait.

        >>> import numpy as np, proxima
        >>> mesh = proxima.Mesh(np.eye(3), [[0, 1, 2]])
        >>> _ = mesh.closest_points([[0, 0, 0]])
        >>> mesh.update_vertices(np.eye(3) * 2)
        [('faces', False, 1.0)]
        """
    @property
    def corner_uvs(self) -> Optional[npt.NDArray[np.float32]]:
        """The file's texture coordinates per face corner, (C, 2) float32 (the
        faces' vertex lists concatenated: a seam keeps two values for one
        vertex), or None. OBJ ``vt`` when every corner of every face names one;
        PLY vertex ``u v`` (or ``s t``, ``texture_u texture_v``)."""
    @property
    def corner_normals(self) -> Optional[npt.NDArray[np.float32]]:
        """The file's shading normals per face corner, (C, 3) float32, or None:
        OBJ ``vn`` when every corner names one, PLY vertex ``nx ny nz``."""
    @property
    def faces(self) -> Union[npt.NDArray[np.int64], list[npt.NDArray[np.int64]]]:
        """The faces: an (F, k) int64 array when every face has k vertices,
        otherwise a list of F int64 arrays."""
    @property
    def used_vertices(self) -> npt.NDArray[np.bool_]:
        """Whether a face uses each vertex, (V,) bool: without making
        :attr:`faces`' arrays, which for a mesh of mixed polygons is a list
        of one array per face."""
    @property
    def bounds(self) -> npt.NDArray[np.float64]:
        """The bounding box, [[min x, min y, min z], [max x, max y, max z]]."""
    def __len__(self) -> int:
        """The number of faces."""
    def closest_points(
        self,
        points: npt.ArrayLike,
        primitives: Primitives = "faces",
        threads: Optional[int] = None,
        *,
        return_barycentric: bool = False,
        return_feature: bool = False,
        return_normal: bool = False,
        return_uv: bool = False,
    ) -> Union[Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.int64]], Answers]:
        """For each of ``points`` (N, 3), the closest point of the mesh's
        ``primitives``: ``(closest (N, 3) float64, distance (N,) float64,
        index (N,) int64)``, the order of trimesh's ``closest_point``.
        ``index`` is the source element: the face (for faces and polygons, a
        polygon face split in triangles still reports its face), the vertex or
        the edge (unique undirected edges in order of first appearance, walking
        each face's edges in order). Computed in float32 on float32 points
        (float64 input is rounded once): the answer of a brute-force scan in
        the same arithmetic, ties to the lowest index.

        With any ``return_*`` option (faces only) the answer is an
        :class:`Answers` that adds ``triangle``, ``corners`` and
        ``barycentric`` (``return_barycentric``), ``feature`` and
        ``feature_vertices`` (``return_feature``), ``normal`` and
        ``face_normal`` (``return_normal``), ``uv`` (``return_uv``); they are
        computed after the query, and cost nothing when not asked.

        >>> closest, distance, face = mesh.closest_points(np.zeros((1, 3)))
        """
    def k_nearest(
        self,
        points: npt.ArrayLike,
        k: int,
        primitives: Primitives = "faces",
        threads: Optional[int] = None,
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]:
        """The ``k`` nearest source elements of each point, nearest first:
        ``(distance (N, k) float64, index (N, k) int64)``. A polygon face
        counts once. Where the mesh has fewer than ``k`` elements, the rest of
        the row is ``inf`` and -1."""
    @overload
    def signed_distance(
        self,
        points: npt.ArrayLike,
        sign: Literal["winding", "pseudonormal"] = "winding",
        threads: Optional[int] = None,
        *,
        return_gradient: Literal[False] = False,
    ) -> npt.NDArray[np.float64]: ...
    @overload
    def signed_distance(
        self,
        points: npt.ArrayLike,
        sign: Literal["winding", "pseudonormal"] = "winding",
        threads: Optional[int] = None,
        *,
        return_gradient: Literal[True],
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def signed_distance(
        self,
        points: npt.ArrayLike,
        sign: Literal["winding", "pseudonormal"] = "winding",
        threads: Optional[int] = None,
        *,
        return_gradient: bool = False,
    ) -> Union[npt.NDArray[np.float64], Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]]:
        """The distance to the closest point of the faces, negative inside,
        shape (N,). ``sign="winding"`` (the default) says inside where the
        generalized winding number exceeds 1/2, right on open and
        self-intersecting meshes; ``"pseudonormal"`` uses the closest
        feature's angle-weighted normal (faster, for closed meshes).

        ``return_gradient=True`` returns ``(distance, gradient (N, 3))``: the
        gradient with respect to the point, ``sign * (p - c) / |p - c|`` (unit
        length, outward; ``c`` the closest point located again in float64);
        for points on the surface (within 16 float32 ulps of their largest
        coordinate) the unit pseudonormal of the closest feature. With
        respect to the closest triangle's corners (``closest_points(...,
        return_barycentric=True)``), feature held fixed, it is
        ``-barycentric[k] * gradient``."""

    def winding_number(self, points: npt.ArrayLike, threads: Optional[int] = None) -> npt.NDArray[np.float64]:
        """The generalized winding number at each point, shape (N,): 1 inside
        a closed outward-oriented mesh, 0 outside, fractional near holes.
        Far triangles are summed by a tree of expansions (Barill et al.):
        within about 0.03 of the exact sum (differences up to 0.017 were seen
        on real meshes); ``contains`` and the sign of ``signed_distance``
        compare it with 1/2."""
    def contains(self, points: npt.ArrayLike, threads: Optional[int] = None) -> npt.NDArray[np.bool_]:
        """Whether each point is inside (winding number above 1/2), shape (N,)."""
    def cast_rays(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        any_hit: bool = False,
        threads: Optional[int] = None,
        *,
        return_barycentric: bool = False,
        return_feature: bool = False,
        return_normal: bool = False,
        return_uv: bool = False,
    ) -> Union[Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]], Answers]:
        """The first face each ray ``origin + t * direction / |direction|``
        (t >= 0) hits: ``(t (N,) float64, index (N,) int64)``, t the distance
        along the normalized direction, ``inf`` and -1 for a miss. Watertight:
        a ray through an edge or a vertex shared by faces hits one of them.
        ``any_hit=True`` returns some hit, not always the first (faster, for
        visibility). The ``return_*`` options add the arrays of
        :meth:`closest_points` (``t`` and ``index`` first) as an
        :class:`Answers`; a miss's rows are -1 and NaN."""
    def voxelize(self, resolution: int, threads: Optional[int] = None) -> VoxelGrid:
        """The cells of a ``resolution``-cubed grid around the mesh that its
        faces overlap (exact triangle/box test). Raises ``ValueError`` when
        ``resolution`` is 0 or the grid would exceed the memory budget
        (``PROXIMA_MEMORY_BUDGET``, bytes)."""
    def frustum(
        self,
        view_projection: npt.ArrayLike,
        primitives: Primitives = "faces",
    ) -> npt.NDArray[np.int64]:
        """The source indices (increasing) of the ``primitives`` that share a
        point with the view frustum of an OpenGL view-projection matrix
        (4, 4), row-major as numpy writes it (``clip = M @ [x, y, z, 1]``)."""
    def built_structures(self) -> list[str]:
        """The names of the structures built so far, in a fixed order:
        ``"vertices"``, ``"edges"``, ``"faces"``, ``"polygons"`` (trees),
        ``"winding"``, ``"pseudonormal"`` (signed-distance fields, on the
        faces' tree), ``"rays"`` (the ray tree). Each is built once, on the
        first call that needs it."""
    def _batch_seconds(
        self,
        points: npt.ArrayLike,
        query: Literal["closest_points", "signed_distance", "cast_rays"],
        directions: Optional[npt.ArrayLike] = None,
        threads: Optional[int] = None,
    ) -> float:
        """For benchmarks: the seconds the Rust batch of ``query`` takes on
        ``points`` (ray origins with ``directions`` for ``cast_rays``), timed
        inside the call, structures already built and no array conversion."""
    def sample_near_surface(self, n: int, sigma: float = 0.01, seed: int = 0) -> npt.NDArray[np.float32]:
        """``n`` points uniform on the faces (by area) plus a gaussian offset
        per axis of standard deviation ``sigma`` times the bounding-box
        diagonal (the benchmarks' ``near`` set), (n, 3) float32, reproducible
        for a seed."""
    def sample_rays(self, n: int, seed: int = 0) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
        """``n`` rays: origins uniform on the sphere of radius 0.75 times the
        bounding-box diagonal around its centre, aimed at points uniform in
        the box, unit directions (the benchmarks' ``rays`` set):
        ``(origins (n, 3), directions (n, 3))`` float32."""
    def sample_uniform(self, n: int, seed: int = 0) -> npt.NDArray[np.float32]:
        """``n`` points uniform in the bounding box enlarged by 10% per side
        (the benchmarks' ``uniform`` set), (n, 3) float32."""
    def training_samples(
        self,
        n: int,
        near_sigma: float,
        uniform_fraction: float = 0.5,
        cube: Optional[float] = None,
        seed: int = 0,
        sign: Literal["winding", "pseudonormal"] = "winding",
        threads: Optional[int] = None,
    ) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
        """Training samples, the recipe of ``proxima sdf --sample`` and
        ``proxima.dataset``: ``(points (n, 3) float32, sdf (n,) float32)``.
        The first ``near`` of ``training_sample_counts(n, uniform_fraction)``
        points are uniform on the faces (by area) plus a gaussian offset per
        axis of standard deviation ``near_sigma``, an absolute length in the
        mesh's units (unlike :meth:`sample_near_surface`'s fraction of the
        diagonal); the rest are uniform in the cube ``[-cube, cube]^3``
        (``cube`` rounded to float32), or in the bounding box grown by 5% per
        side when ``cube`` is None. ``sdf`` is the signed distance (negative
        inside, the side by ``sign``). The same arguments give the same arrays
        on every machine and thread count, and the same as ``proxima sdf MESH
        --sample n --near-sigma near_sigma --uniform-fraction uniform_fraction
        --cube cube --seed seed``. ``ValueError`` naming ``n`` (memory
        budget), ``near_sigma``, ``uniform_fraction`` or ``cube`` when out of
        range, and for a mesh without faces or without area."""
    def sdf_grid(
        self,
        resolution: int,
        cube: Optional[float] = None,
        sign: Literal["winding", "pseudonormal"] = "winding",
        threads: Optional[int] = None,
    ) -> npt.NDArray[np.float32]:
        """The signed distances at the centres of ``resolution``^3 cells
        dividing the cube ``[-cube, cube]^3`` (or the bounding box grown by 5%
        per side when ``cube`` is None), as ``proxima sdf --grid N [--cube
        H]`` computes them: (N, N, N) float32 in C order, ``[i, j, k]`` at
        ``(x_i, y_j, z_k)``, ``x_i = lo + cell * (i + 0.5)`` in float32
        (``cell = (hi - lo) / N``). ``ValueError`` naming ``resolution``
        (below 1, or 8 bytes a cell beyond the memory budget) or ``cube``."""

    def intersects(
        self,
        other: Mesh,
        pose: Optional[Pose] = None,
        *,
        pose_self: Optional[Pose] = None,
        threads: Optional[int] = None,
    ) -> Union[bool, npt.NDArray[np.bool_]]:
        """Whether this mesh's surface, placed by ``pose_self``, meets
        ``other``'s placed by ``pose`` (``None``: the identity): closed
        triangles, touching counts, decided exactly for the placed float64
        coordinates. Surfaces, not volumes: a mesh wholly inside another does
        not meet it. ``pose`` of shape (P, 4, 4): (P,) bool, ``other`` at
        each pose with this mesh unmoved (``pose_self`` None). ``ValueError``
        naming ``self``/``other`` (no faces), ``pose``, ``pose_self``,
        ``threads``."""
    def intersecting_pairs(
        self,
        other: Mesh,
        pose: Optional[Pose] = None,
        *,
        pose_self: Optional[Pose] = None,
        threads: Optional[int] = None,
    ) -> npt.NDArray[np.int64]:
        """The pairs of faces (face of this mesh, face of ``other``) that
        meet, decided exactly as :meth:`intersects`: (K, 2) int64, sorted,
        each pair once (a polygon face meets if any of its fan triangles
        does)."""
    def pairs_within(
        self,
        other: Mesh,
        distance: float,
        pose: Optional[Pose] = None,
        *,
        pose_self: Optional[Pose] = None,
        threads: Optional[int] = None,
    ) -> npt.NDArray[np.int64]:
        """The pairs of faces at distance at most ``distance`` (float64
        triangle-pair distance; ``distance=0`` is exactly
        :meth:`intersecting_pairs`): (K, 2) int64, sorted. ``ValueError``
        naming ``distance`` when it is negative, NaN or infinite."""
    def self_intersections(self, threads: Optional[int] = None) -> npt.NDArray[np.int64]:
        """The pairs of faces ``[f, g]`` (``f < g``) of this mesh that meet,
        decided exactly: (K, 2) int64, sorted. Faces sharing vertices (by
        index) are reported only when they meet beyond what they share (a
        fold, a face crossing its neighbour); faces meeting through distinct
        but equal vertices (an unwelded seam) are reported: weld first. The
        same pairs as ``proxima self-intersections``."""

class Points:
    """A point cloud and its tree, for neighbour queries. ``points`` (N, 3),
    float32 read without a copy (float64 and integers converted once);
    ``ValueError`` naming ``points`` when it is empty or a point is not
    finite. Queries return nearest first, ties by index; radius queries are
    exact: a point exactly at distance ``r`` is in, one ulp farther is
    out. Every call releases the GIL and runs on ``threads`` (all cores by
    default)."""

    def __init__(self, points: npt.ArrayLike, threads: Optional[int] = None) -> None: ...
    def __len__(self) -> int: ...
    @property
    def points(self) -> npt.NDArray[np.float32]:
        """The points, (N, 3) float32."""
    def k_nearest(
        self, queries: npt.ArrayLike, k: int, threads: Optional[int] = None
    ) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.int64]]:
        """``(distance, index)``, each (Q, k): the ``k`` nearest points of
        each query, padded with ``inf`` and ``-1`` when the cloud has fewer
        (scipy's ``cKDTree.query`` layout). ``ValueError`` naming ``k``
        (below 1 or above 2**31, or answers beyond the memory budget) or
        ``queries[i]``."""
    def within(
        self,
        queries: npt.ArrayLike,
        r: float,
        max_neighbors: Optional[int] = None,
        threads: Optional[int] = None,
    ) -> Tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.float32]]:
        """``(offsets, index, distance)`` in compressed rows: query ``i``'s
        neighbours are ``index[offsets[i]:offsets[i + 1]]``, every point at
        distance at most ``r`` (exactly), nearest first; with
        ``max_neighbors``, only the nearest that many (the ball query of
        PointNet++). ``ValueError`` naming ``r`` (negative or NaN; or
        answers beyond the memory budget) or ``max_neighbors``."""
    def count_within(
        self, queries: npt.ArrayLike, r: float, threads: Optional[int] = None
    ) -> npt.NDArray[np.int64]:
        """How many points lie within ``r`` of each query (exactly), (Q,)."""
    def pairs_within(self, r: float, threads: Optional[int] = None) -> npt.NDArray[np.int64]:
        """Every pair ``(i, j)``, ``i < j``, of points at distance at most
        ``r`` (exactly): (K, 2) int64, sorted."""

def chamfer(
    a: Union[Points, npt.ArrayLike],
    b: Union[Points, npt.ArrayLike],
    squared: bool = True,
    threads: Optional[int] = None,
) -> float:
    """The Chamfer distance between point sets ``a`` and ``b``: the mean
    nearest distance from ``a`` to ``b`` plus from ``b`` to ``a``, of squared
    distances (``squared=True``: pytorch3d's ``chamfer_distance``) or plain
    ones (point-cloud-utils' ``chamfer_distance``); sums in float64."""

@overload
def hausdorff(
    a: Union[Points, npt.ArrayLike],
    b: Union[Points, npt.ArrayLike],
    one_sided: bool = False,
    *,
    threads: Optional[int] = None,
) -> float:
    """The Hausdorff distance between point sets ``a`` and ``b``: the
    largest distance from a point of either set to the other (with
    ``one_sided``, from ``a`` to ``b`` only)."""

@overload
def hausdorff(
    a: Mesh,
    b: Mesh,
    one_sided: bool = False,
    *,
    tolerance: Optional[float] = None,
    threads: Optional[int] = None,
) -> Hausdorff:
    """The Hausdorff distance between the surfaces of meshes ``a`` and ``b``
    (both in the same frame), as a :class:`Hausdorff`: a lower bound (the
    distance of an actual point of one surface to the other) and an upper
    bound that meet within ``tolerance`` (default 1e-4 of the larger
    bounding-box diagonal; at least 1e-7 of it, else ``ValueError``),
    refined where the bound is loose (``proxima::pair::hausdorff``). With
    ``one_sided``, from ``a``'s surface to ``b``'s only."""

class Scene:
    """Meshes placed by rigid poses, asked as one: closest points, signed
    distance of the union, first and any hit, each answer naming the
    instance and its face. The same ``Mesh`` placed several times shares
    its structures (built once, on first use). A top-level tree over the
    instances' world boxes sends each query to the instances it concerns;
    there it is carried into the mesh's frame (float64, rounded once to
    float32) and answered by the mesh's own trees. Answers are brute force's
    over every placed triangle, up to that rounding; ties between instances
    go to the lower index. ``set_pose`` refits the top level only.

    A mesh placed in a scene cannot ``update_vertices`` (the scene shares its
    structures): ``ValueError`` naming ``positions``.

    >>> import numpy as np, proxima
    >>> sphere = proxima.noisy_icosphere(8)
    >>> moved = np.eye(4); moved[0, 3] = 5.0
    >>> scene = proxima.Scene([(sphere, None), (sphere, moved)])
    >>> closest, distance, instance, face = scene.closest_points([[4.0, 0.0, 0.0]])
    >>> instance.tolist()
    [1]
    """

    def __init__(self, instances: Sequence[Tuple[Mesh, Optional[npt.ArrayLike]]]) -> None:
        """``instances``: (mesh, pose) pairs, pose a (4, 4) rigid matrix
        (rotation and translation; mirrors and scales refused) or None for
        the identity. ``ValueError`` naming ``instances[i]`` for a pair that
        is not one, ``instances[i][1]`` for a bad pose, ``instances`` for a
        mesh without faces."""
    def __len__(self) -> int: ...
    def pose(self, index: int) -> npt.NDArray[np.float64]:
        """The pose of instance ``index``, (4, 4) float64."""
    def set_pose(self, index: int, pose: npt.ArrayLike) -> None:
        """Moves instance ``index`` to ``pose`` (a (4, 4) rigid matrix): the
        top level is refit (rebuilt once refits made it 1.5 times costlier),
        the meshes' own trees are not touched: microseconds. ``ValueError``
        naming ``index`` out of range, ``pose`` for a pose that is not rigid."""
    def update_vertices(self, index: int, positions: npt.ArrayLike) -> list[tuple[str, bool, float]]:
        """Moves the vertices of instance ``index``'s mesh to ``positions``
        ((V, 3), one row per vertex in order; the faces stay): every
        instance of that mesh deforms with it, and the scene then answers as
        a new ``Scene`` over the moved vertices.

        The scene shares each mesh's structures with the ``Mesh`` you gave
        it. The first time a mesh is deformed in the scene, the scene makes
        a copy of its own (structures built on first use; returns ``[]``)
        and your ``Mesh`` keeps its vertices. Later calls find that copy
        unshared and update its structures in place, as
        ``Mesh.update_vertices`` does, returning ``(structure, rebuilt,
        cost_ratio)`` per structure. The top level is refit as by
        ``set_pose``.

        Raises ValueError naming ``index`` out of range, or ``positions``
        for another vertex count, a NaN or infinite coordinate, or one
        beyond the coordinate bound; the scene is then unchanged. The GIL
        is released.

        >>> import numpy as np, proxima
        >>> mesh = proxima.Mesh(np.eye(3), [[0, 1, 2]])
        >>> scene = proxima.Scene([(mesh, None), (mesh, np.diag([1.0, 1, 1, 1]))])
        >>> scene.update_vertices(1, np.eye(3) * 2)
        []
        >>> float(scene.closest_points([[0, 0, 0]])[1][0]) > 1.1
        True
        >>> mesh.vertices[0].tolist()
        [1.0, 0.0, 0.0]
        """
    def closest_points(
        self, points: npt.ArrayLike, threads: Optional[int] = None
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.int64]]:
        """``(closest (N, 3), distance (N,), instance (N,), face (N,))``, the
        closest point in world coordinates; NaN, inf and -1 for an empty scene."""
    def k_nearest(
        self, points: npt.ArrayLike, k: int, threads: Optional[int] = None
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.int64]]:
        """The ``k`` faces of any instances nearest to each point, nearest
        first (ties by instance, then face; a face once, at its nearest
        point): ``(distance (N, k), instance (N, k), face (N, k))``, padded
        with inf and -1 where the scene has fewer faces. ``ValueError``
        naming ``k`` below 1 or beyond the memory budget."""
    def signed_distance(
        self, points: npt.ArrayLike, sign: Literal["winding", "pseudonormal"] = "winding", threads: Optional[int] = None
    ) -> npt.NDArray[np.float64]:
        """The scene's signed distance, (N,) float64: the distance to the
        closest point of any instance, negative where the point is inside
        any instance (the union of their solids), each signed by ``sign``."""
    def contains(
        self, points: npt.ArrayLike, sign: Literal["winding", "pseudonormal"] = "winding", threads: Optional[int] = None
    ) -> npt.NDArray[np.bool_]:
        """Whether each point is inside some instance, (N,) bool."""
    def cast_rays(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        any_hit: bool = False,
        threads: Optional[int] = None,
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.int64]]:
        """The first hit of each ray on any instance (with ``any_hit``, some
        hit, found sooner): ``(t (N,), instance (N,), face (N,))``; ``inf``
        and -1 for a miss. Directions are normalized: ``t`` is a distance."""

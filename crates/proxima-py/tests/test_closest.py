"""closest_points and k_nearest against numpy brute force and libigl."""

import zlib

import numpy as np
import pytest

import oracles as o
import proxima
from conftest import (
    cube_arrays,
    cube_quads,
    load_shared,
    quad_grid_arrays,
    query_points,
    random_soup,
)

RTOL = 1e-6
F32_EPS = float(np.finfo(np.float32).eps)


def atol_of(vertices, points=None):
    """Absolute tolerance: a few float32 ulps of the coordinates' magnitude
    (the closest points come back as float32 values), at least 1e-7 of the
    mesh's size."""
    v = np.asarray(vertices, dtype=np.float64)
    mag = np.abs(v).max()
    if points is not None and len(points):
        mag = max(mag, np.abs(points).max())
    return max(4 * F32_EPS * mag, 1e-7 * scale_of(v))


def _mesh_cases():
    cases = {}
    for n, seed in ((30, 1), (100, 2), (250, 3)):
        cases[f"soup{n}"] = random_soup(n, seed)
    cases["cube"] = cube_arrays()
    ico = proxima.noisy_icosphere(4)
    cases["icosphere4"] = (ico.vertices, ico.faces)
    return cases


MESHES = _mesh_cases()


def scale_of(v):
    v = np.asarray(v, dtype=np.float64)
    return float(np.linalg.norm(v.max(0) - v.min(0)))


def element_of(vertices, faces, primitives, index, points):
    """Distance from each point to its own indexed element (pairwise)."""
    v = np.asarray(vertices, dtype=np.float64)
    if primitives == "vertices":
        return np.linalg.norm(points - v[index], axis=1)
    if primitives == "edges":
        e = o.unique_edges(faces)[index]
        return o.seg_dist(points, v[e[:, 0]], v[e[:, 1]])
    tris, src = o.fan_triangles(faces)
    out = np.full(len(points), np.inf)
    for t, f in enumerate(src):
        sel = index == f
        if sel.any():
            a, b, c = v[tris[t]]
            out[sel] = np.minimum(out[sel], o.tri_dist(points[sel], a, b, c))
    return out


def check_closest(mesh, vertices, faces, primitives, points, tie_gap=1e-5):
    """The checks of one closest_points call against brute force; returns the
    number of points whose nearest element is unique (index compared exactly)."""
    closest, distance, index = mesh.closest_points(points, primitives=primitives)
    scale = scale_of(vertices)
    atol = atol_of(vertices, points)
    bf = o.element_distances(points, vertices, faces, primitives)
    best = bf.min(axis=1)
    n = len(points)
    assert closest.shape == (n, 3) and distance.shape == (n,) and index.shape == (n,)
    # 1. the distance is the brute-force minimum
    np.testing.assert_allclose(distance, best, rtol=RTOL, atol=atol, err_msg=f"{primitives}: distance")
    # 2. the closest point is at that distance from the query ...
    np.testing.assert_allclose(
        np.linalg.norm(closest - points, axis=1), distance, rtol=RTOL, atol=atol, err_msg=f"{primitives}: |closest - p|"
    )
    # 3. ... and lies on the indexed element
    assert index.min() >= 0 and index.max() < bf.shape[1]
    on = element_of(vertices, faces, primitives, index, closest)
    assert np.all(on <= atol), f"{primitives}: closest point off its element: {on.max()}"
    # 4. the indexed element is at the minimum distance (ties allowed)
    np.testing.assert_allclose(bf[np.arange(n), index], best, rtol=RTOL, atol=atol, err_msg=f"{primitives}: element")
    # 5. where the nearest element is clearly unique, the index is exactly it
    srt = np.sort(bf, axis=1)
    unique = (srt[:, 1] - srt[:, 0] > tie_gap * (srt[:, 0] + scale)) if bf.shape[1] > 1 else np.ones(n, bool)
    bad = np.nonzero(unique & (index != bf.argmin(axis=1)))[0]
    assert len(bad) == 0, (
        f"{primitives}: {len(bad)} points whose unique nearest element differs, e.g. point {points[bad[0]].tolist()}: "
        f"index {index[bad[0]]} (d={bf[bad[0], index[bad[0]]]}) vs brute force {bf[bad[0]].argmin()} (d={best[bad[0]]})"
    )
    return int(unique.sum())


@pytest.mark.parametrize("name", list(MESHES))
@pytest.mark.parametrize("primitives", ["faces", "vertices", "edges", "polygons"])
def test_closest_points_brute_force(name, primitives):
    v, f = MESHES[name]
    mesh = proxima.Mesh(v, f)
    pts = query_points(v, 600, seed=zlib.crc32(name.encode()))
    unique = check_closest(mesh, v, f, primitives, pts)
    assert unique > 0.25 * len(pts)  # the exact index check did some of the work


def test_edge_numbering_claim():
    """The library's edge numbering (first appearance, each face's edges
    (v0,v1),...,(vk-1,v0)) is the one oracles.unique_edges derives: for every
    edge, a query point just off its midpoint finds that very edge."""
    for name in ("icosphere4", "cube", "soup30"):
        v, f = MESHES[name]
        mesh = proxima.Mesh(v, f)
        edges = o.unique_edges(f)
        vv = np.asarray(v, dtype=np.float64)
        mid = (vv[edges[:, 0]] + vv[edges[:, 1]]) / 2
        # move the query off the edge, away from the mesh's center: closest edge is still it
        off = mid - vv.mean(0)
        pts = o.f32(mid + 1e-3 * off / np.linalg.norm(off, axis=1, keepdims=True))
        bf = o.edge_distances(pts, vv, edges)
        clear = np.sort(bf, 1)[:, 1] > 2 * bf.min(1)
        _, _, index = mesh.closest_points(pts, primitives="edges")
        assert clear.sum() > 0.9 * len(edges)
        np.testing.assert_array_equal(index[clear], np.arange(len(edges))[clear], err_msg=name)


def test_edges_count_matches_numbering():
    v, f = MESHES["icosphere4"]
    mesh = proxima.Mesh(v, f)
    ne = len(o.unique_edges(f))
    assert ne == 480  # 320 triangles of a closed sphere: E = 3F/2
    dist, index = mesh.k_nearest(np.zeros((1, 3)), ne + 5, primitives="edges")
    assert sorted(index[0, :ne].tolist()) == list(range(ne))
    assert np.all(index[0, ne:] == -1) and np.all(np.isinf(dist[0, ne:]))


# --- polygons ------------------------------------------------------------------------


@pytest.mark.parametrize("primitives", ["polygons", "faces", "edges", "vertices"])
def test_closest_points_quad_mesh(primitives):
    v, f = quad_grid_arrays()
    mesh = proxima.Mesh(v, f)
    pts = query_points(v, 600, seed=11)
    check_closest(mesh, v, f, primitives, pts)


def test_polygons_report_their_face():
    """A quad split in triangles still reports its face, for both primitives."""
    v, _ = cube_arrays()
    quads = cube_quads()
    mesh = proxima.Mesh(v, quads)
    # points in front of each quad's center, clearly nearest to that quad
    vv = v.astype(np.float64)
    centers = vv[quads].mean(axis=1)
    pts = o.f32(centers + 0.2 * (centers - 0.5))
    for prim in ("faces", "polygons"):
        _, d, idx = mesh.closest_points(pts, primitives=prim)
        np.testing.assert_array_equal(idx, np.arange(6), err_msg=prim)
        np.testing.assert_allclose(d, 0.1, rtol=1e-6)


def test_mixed_polygon_sizes():
    """A list of faces of different lengths (triangle, quad, pentagon)."""
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0], [3, 0.5, 0], [0, 0, 1]], np.float32)
    faces = [[0, 1, 2, 3], [1, 4, 6, 5, 2], [0, 3, 7]]
    mesh = proxima.Mesh(v, faces)
    pts = query_points(v, 300, seed=5)
    for prim in ("faces", "polygons", "edges", "vertices"):
        check_closest(mesh, v, faces, prim, pts)


# --- ties ----------------------------------------------------------------------------


def test_ties_go_to_lowest_index():
    """Exact ties: the nearest point is a vertex shared by several elements."""
    v, f = cube_arrays()
    mesh = proxima.Mesh(v, f)
    vv = v.astype(np.float64)
    edges = o.unique_edges(f)
    for corner in range(8):
        p = (vv[corner] - 0.5) * 3 + 0.5  # outside, beyond the corner
        _, d, face = mesh.closest_points(p[None], primitives="faces")
        assert d[0] == pytest.approx(np.linalg.norm(p - vv[corner]), rel=1e-7)
        assert face[0] == min(i for i, t in enumerate(f) if corner in t), f"corner {corner}"
        _, _, edge = mesh.closest_points(p[None], primitives="edges")
        assert edge[0] == min(i for i, e in enumerate(edges) if corner in e), f"corner {corner}"


def test_duplicate_vertices_tie():
    """Two vertices at the same position: vertices ties go to the lower one."""
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0]], np.float32)
    mesh = proxima.Mesh(v, [[0, 1, 2], [3, 2, 0]])
    _, d, idx = mesh.closest_points([[2.0, 0.0, 0.0]], primitives="vertices")
    assert idx.tolist() == [1] and d.tolist() == [1.0]
    # the duplicate face: faces 0 and 1 are the same triangle
    _, d, idx = mesh.closest_points([[0.25, 0.25, 1.0]], primitives="faces")
    assert idx.tolist() == [0] and d.tolist() == [1.0]


# --- k_nearest -----------------------------------------------------------------------


@pytest.mark.parametrize("name", ["soup100", "cube", "icosphere4", "quads"])
@pytest.mark.parametrize("primitives", ["faces", "vertices", "edges", "polygons"])
def test_k_nearest_brute_force(name, primitives):
    v, f = quad_grid_arrays() if name == "quads" else MESHES[name]
    mesh = proxima.Mesh(v, f)
    pts = query_points(v, 200, seed=7)
    bf = o.element_distances(pts, v, f, primitives)
    atol = atol_of(v, pts)
    for k in (1, 4, 17):
        dist, idx = mesh.k_nearest(pts, k, primitives=primitives)
        assert dist.shape == (len(pts), k) and idx.shape == (len(pts), k)
        assert dist.dtype == np.float64 and idx.dtype == np.int64
        kk = min(k, bf.shape[1])
        expect = np.sort(bf, axis=1)[:, :kk]
        np.testing.assert_allclose(dist[:, :kk], expect, rtol=RTOL, atol=atol)
        # each index is a distinct element at its reported distance
        got = np.take_along_axis(bf, idx[:, :kk], axis=1)
        np.testing.assert_allclose(got, dist[:, :kk], rtol=RTOL, atol=atol)
        assert all(len(set(r)) == kk for r in idx[:, :kk].tolist())
        assert np.all(np.diff(dist[:, :kk], axis=1) >= 0)
        # k = 1 agrees with closest_points
        if k == 1:
            _, d1, i1 = mesh.closest_points(pts, primitives=primitives)
            np.testing.assert_array_equal(dist[:, 0], d1)
            np.testing.assert_array_equal(idx[:, 0], i1)


def test_k_nearest_padding():
    v, f = cube_arrays()
    mesh = proxima.Mesh(v, f)
    pts = np.array([[0.5, 0.5, 3.0], [2.0, -1.0, 0.5]])
    for prim, count in (("faces", 12), ("vertices", 8), ("edges", 18)):
        dist, idx = mesh.k_nearest(pts, count + 3, primitives=prim)
        assert np.all(np.isfinite(dist[:, :count])) and np.all(idx[:, :count] >= 0)
        assert np.all(np.isinf(dist[:, count:])) and np.all(dist[:, count:] > 0)
        assert np.all(idx[:, count:] == -1)
        assert sorted(idx[0, :count].tolist()) == list(range(count))
    # polygons: a polygon face counts once
    quad_mesh = proxima.Mesh(v, cube_quads())
    for prim in ("faces", "polygons"):
        dist, idx = quad_mesh.k_nearest(pts, 8, primitives=prim)
        assert sorted(idx[0, :6].tolist()) == list(range(6)), prim
        assert idx[0, 6:].tolist() == [-1, -1] and np.all(np.isinf(dist[:, 6:]))


@pytest.mark.parametrize("k", [0, -1, -100])
def test_k_nearest_k_below_one(k, cube):
    with pytest.raises(ValueError, match="k"):
        cube.k_nearest(np.zeros((2, 3)), k)


# --- libigl on real meshes -----------------------------------------------------------


def near_surface_points(vertices, faces, n, seed, sigma=0.01):
    """Uniform-by-area points on the faces plus gaussian noise (numpy only)."""
    rng = np.random.default_rng(seed)
    v = np.asarray(vertices, dtype=np.float64)
    tris, _ = o.fan_triangles(faces)
    a, b, c = v[tris[:, 0]], v[tris[:, 1]], v[tris[:, 2]]
    area = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    t = rng.choice(len(tris), n, p=area / area.sum())
    r1, r2 = rng.random(n), rng.random(n)
    s = np.sqrt(r1)
    p = (1 - s)[:, None] * a[t] + (s * (1 - r2))[:, None] * b[t] + (s * r2)[:, None] * c[t]
    diag = np.linalg.norm(v.max(0) - v.min(0))
    return o.f32(p + rng.normal(0, sigma * diag, p.shape))


@pytest.mark.parametrize(
    "name", ["bunny-npm.obj", "spot_triangulated.obj", "fandisk.obj", "dragon_vrip_res2.ply"]
)
def test_closest_points_vs_libigl(name):
    igl = pytest.importorskip("igl")
    mesh = load_shared(name)
    v = mesh.vertices.astype(np.float64)
    f = np.ascontiguousarray(mesh.faces, dtype=np.int64)
    pts = near_surface_points(v, f, 3000, seed=1)
    sqd, _, _ = igl.point_mesh_squared_distance(pts, v, f)
    closest, dist, face = mesh.closest_points(pts)
    atol = atol_of(v, pts)
    np.testing.assert_allclose(dist, np.sqrt(sqd), rtol=RTOL, atol=atol)
    # the indexed face is at that distance, and holds the closest point
    a, b, c = v[f[face, 0]], v[f[face, 1]], v[f[face, 2]]
    np.testing.assert_allclose(o.tri_dist(pts, a, b, c), dist, rtol=RTOL, atol=atol)
    assert np.all(o.tri_dist(closest, a, b, c) <= atol)

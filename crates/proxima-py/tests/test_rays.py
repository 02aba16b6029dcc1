"""cast_rays against a numpy brute-force Moller-Trumbore over all triangles."""

import numpy as np
import pytest

import oracles as o
import proxima
from conftest import cube_arrays, random_soup

EDGE_TOL = 1e-6  # rays this close to an edge (relative to the mesh size) may disagree


def meshes():
    out = {f"soup{n}": random_soup(n, seed) for n, seed in ((40, 21), (200, 22))}
    out["cube"] = cube_arrays()
    ico = proxima.noisy_icosphere(4)
    out["icosphere4"] = (ico.vertices, ico.faces)
    return out


MESHES = meshes()


def random_rays(v, f, n, seed):
    """Half the rays aimed at random points of random triangles (so they hit
    often), half in random directions; origins around the mesh; direction
    lengths vary (the t must not depend on them). float32-rounded."""
    rng = np.random.default_rng(seed)
    v = np.asarray(v, dtype=np.float64)
    lo, hi = v.min(0), v.max(0)
    size = np.max(hi - lo)
    origins = lo - 0.5 * size + rng.random((n, 3)) * (hi - lo + size)
    tri = v[f[rng.integers(0, len(f), n)]]
    w = rng.dirichlet([1, 1, 1], n)
    target = np.einsum("nk,nkj->nj", w, tri)
    aimed = target - origins
    random = rng.normal(size=(n, 3)) * rng.uniform(0.1, 10, (n, 1))
    directions = np.where((np.arange(n) % 2 == 0)[:, None], aimed, random)
    return o.f32(origins), o.f32(directions)


def boundary_distance(points, tri):
    """Distance from points to the boundary (three edges) of their triangles (n, 3, 3)."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    return np.minimum(np.minimum(o.seg_dist(points, a, b), o.seg_dist(points, b, c)), o.seg_dist(points, c, a))


@pytest.mark.parametrize("name", list(MESHES))
def test_cast_rays_brute_force(name):
    v, f = MESHES[name]
    vv = np.asarray(v, dtype=np.float64)
    mesh = proxima.Mesh(v, f)
    origins, directions = random_rays(v, f, 2000, seed=len(f))
    unit = directions / np.linalg.norm(directions, axis=1, keepdims=True)
    scale = np.linalg.norm(vv.max(0) - vv.min(0))
    tol = EDGE_TOL * scale
    t, idx = mesh.cast_rays(origins, directions)
    assert t.shape == (len(origins),) and t.dtype == np.float64 and idx.dtype == np.int64
    bt_all = o.moller_trumbore(origins, unit, vv, f)
    bt = bt_all.min(axis=1)
    bf = np.where(np.isfinite(bt), bt_all.argmin(axis=1), -1)
    hit, bhit = idx >= 0, np.isfinite(bt)
    assert bhit.mean() > 0.3  # the test is about hits, mostly
    # misses are inf / -1, hits finite >= 0
    assert np.all(np.isinf(t[~hit])) and np.all(np.isfinite(t[hit])) and np.all(t[hit] >= 0)
    # every reported hit is on its face at that t
    tri_v = vv[f]
    p = origins[hit] + t[hit, None] * unit[hit]
    on = o.tri_dist(p, tri_v[idx[hit], 0], tri_v[idx[hit], 1], tri_v[idx[hit], 2])
    assert np.all(on <= tol), f"hit point off its face by {on.max()}"
    # first hit: the same t as brute force, except rays grazing an edge
    grazing = np.zeros(len(t), bool)
    bh = np.nonzero(bhit)[0]
    grazing[bh] = boundary_distance(origins[bh] + bt[bh, None] * unit[bh], tri_v[bf[bh]]) <= tol
    ph = np.nonzero(hit)[0]
    grazing[ph] |= boundary_distance(origins[ph] + t[ph, None] * unit[ph], tri_v[idx[ph]]) <= tol
    both = hit & bhit
    # t is float32 arithmetic: its error grows as 1/cos of the incidence angle
    cos = np.ones(len(t))
    if ph.size:
        n = np.cross(tri_v[idx[ph], 1] - tri_v[idx[ph], 0], tri_v[idx[ph], 2] - tri_v[idx[ph], 0])
        cos[ph] = np.abs(np.sum(n * unit[ph], 1)) / np.linalg.norm(n, axis=1)
    with np.errstate(invalid="ignore"):
        close = np.abs(t - bt) * np.maximum(cos, 1e-3) <= 1e-6 * (scale + np.abs(bt))
    bad = np.nonzero(((hit != bhit) | (both & ~close)) & ~grazing)[0]
    assert len(bad) == 0, (
        f"{len(bad)} rays disagree, e.g. origin {origins[bad[0]].tolist()} direction {directions[bad[0]].tolist()}: "
        f"proxima t={t[bad[0]]} face {idx[bad[0]]}, brute force t={bt[bad[0]]} face {bf[bad[0]]}"
    )
    assert grazing.sum() <= 0.01 * len(t)
    # any_hit: some real hit whenever the first hit hits, a miss otherwise
    ta, ia = mesh.cast_rays(origins, directions, any_hit=True)
    np.testing.assert_array_equal(ia >= 0, hit)
    pa = origins[hit] + ta[hit, None] * unit[hit]
    on = o.tri_dist(pa, tri_v[ia[hit], 0], tri_v[ia[hit], 1], tri_v[ia[hit], 2])
    assert np.all(on <= tol) and np.all(ta[hit] >= t[hit] - 1e-6 * scale)
    assert np.all(np.isinf(ta[~hit]))


def test_t_along_normalized_direction(cube):
    origins = np.array([[0.5, 0.5, -2.0]] * 3 + [[-1.0, 0.5, 0.5]])
    directions = np.array([[0, 0, 1e-3], [0, 0, 1], [0, 0, 1e3], [5, 0, 0]], dtype=np.float64)
    t, idx = cube.cast_rays(origins, directions)
    np.testing.assert_allclose(t, [2, 2, 2, 1], rtol=1e-7)
    assert np.all(idx >= 0)
    t, idx = cube.cast_rays([[0.5, 0.5, -2.0]], [[0, 0, -1]])
    assert t.tolist() == [np.inf] and idx.tolist() == [-1]


def test_rays_at_vertices_and_edges_of_closed_mesh_never_miss():
    """Watertight: rays through a vertex or an edge shared by faces hit."""
    ico = proxima.noisy_icosphere(4)
    v = ico.vertices.astype(np.float64)
    f = ico.faces
    edges = o.unique_edges(f)
    targets = np.concatenate([v, (v[edges[:, 0]] + v[edges[:, 1]]) / 2])
    rng = np.random.default_rng(8)
    for origins in (
        np.zeros_like(targets),  # from inside
        targets * 3 + rng.normal(0, 0.3, targets.shape),  # from outside
    ):
        t, idx = ico.cast_rays(origins, targets - origins)
        assert np.all(idx >= 0), f"{np.sum(idx < 0)} rays through vertices/edges missed"
        t2, idx2 = ico.cast_rays(origins, targets - origins, any_hit=True)
        assert np.all(idx2 >= 0)
    # the cube: rays through the corners and edges, axis-aligned origins
    cv, cf = cube_arrays()
    cube = proxima.Mesh(cv, cf)
    cv = cv.astype(np.float64)
    ce = o.unique_edges(cf)
    targets = np.concatenate([cv, (cv[ce[:, 0]] + cv[ce[:, 1]]) / 2])
    t, idx = cube.cast_rays(np.full_like(targets, 0.5), targets - 0.5)
    assert np.all(idx >= 0)
    np.testing.assert_allclose(t, np.linalg.norm(targets - 0.5, axis=1), rtol=1e-6)


def test_rays_from_inside_closed_mesh_always_hit():
    ico = proxima.noisy_icosphere(4)
    rng = np.random.default_rng(1)
    d = rng.normal(size=(5000, 3))
    origins = rng.normal(0, 0.1, (5000, 3))
    t, idx = ico.cast_rays(origins, d)
    assert np.all(idx >= 0)
    assert np.all((t > 0.5) & (t < 1.6))

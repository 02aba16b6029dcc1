"""frustum against numpy brute force on the clip-space inequalities."""

import numpy as np
import pytest

import oracles as o
import proxima
from conftest import quad_grid_arrays, random_soup


def cameras(seed, n=6):
    """Perspective view-projection matrices looking at the origin from random
    eyes, with near/far planes that cut the unit-ish meshes."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        eye = rng.normal(size=3)
        eye *= rng.uniform(1.5, 4) / np.linalg.norm(eye)
        target = rng.normal(0, 0.3, 3)
        dist = np.linalg.norm(eye - target)
        proj = o.perspective(rng.uniform(20, 70), rng.uniform(0.5, 2), dist - 0.6, dist + 0.3)
        out.append(proj @ o.look_at(eye, target, [0, 1, 0]))
    return out


def orthographic(l, r, b, t, n, f):
    m = np.eye(4)
    m[0, 0], m[1, 1], m[2, 2] = 2 / (r - l), 2 / (t - b), -2 / (f - n)
    m[:3, 3] = [-(r + l) / (r - l), -(t + b) / (t - b), -(f + n) / (f - n)]
    return m


def inside_vertices(matrix, v):
    """(inside, ambiguous) per vertex, float64 on the float32 matrix."""
    m = o.f32(matrix)
    marg = o.frustum_margins(m, v)
    inside = np.all(marg >= 0, axis=1)
    scale = np.abs(m).sum(axis=1).max() * (1 + np.abs(v).max())
    ambiguous = np.any(np.abs(marg) <= 1e-9 * scale, axis=1)
    return inside, ambiguous, marg


def check_elements(name, got, elements, vin, vamb, marg):
    """Every element with a vertex clearly inside is returned; every returned
    element is not wholly outside one plane (a necessary condition to meet
    the frustum, stronger than its bounding box's)."""
    assert got.dtype == np.int64 and got.ndim == 1
    assert np.all(np.diff(got) > 0), f"{name}: not increasing/unique"
    returned = np.zeros(len(elements), bool)
    returned[got] = True
    has_inside = np.array([np.any(vin[e] & ~vamb[e]) for e in elements])
    missing = np.nonzero(has_inside & ~returned)[0]
    assert len(missing) == 0, f"{name}: {len(missing)} elements with a vertex inside not returned, e.g. {missing[:5]}"
    outside_one_plane = np.array([np.any(np.all(marg[e] < 0, axis=0)) and not vamb[e].any() for e in elements])
    extra = np.nonzero(outside_one_plane & returned)[0]
    assert len(extra) == 0, f"{name}: {len(extra)} returned elements wholly outside a plane, e.g. {extra[:5]}"


@pytest.mark.parametrize("mesh_name", ["icosphere8", "soup"])
def test_frustum_brute_force(mesh_name):
    if mesh_name == "soup":
        v, f = random_soup(400, 41)
        v = (v * 2 - 1).astype(np.float32)
    else:
        ico = proxima.noisy_icosphere(8)
        v, f = ico.vertices, ico.faces
    mesh = proxima.Mesh(v, f)
    vv = np.asarray(v, dtype=np.float64)
    edges = o.unique_edges(f)
    counts = []
    for m in cameras(5) + [orthographic(-0.5, 0.7, -0.6, 0.4, 0.5, 3.0) @ o.look_at([0, 0, 2], [0, 0, 0], [0, 1, 0])]:
        vin, vamb, marg = inside_vertices(m, vv)
        got = mesh.frustum(m, primitives="vertices")
        expect = np.nonzero(vin)[0]
        clear_expect = np.nonzero(vin & ~vamb)[0]
        assert set(clear_expect) <= set(got.tolist()) <= set(expect.tolist()) | set(np.nonzero(vamb)[0].tolist())
        assert got.dtype == np.int64 and np.all(np.diff(got) > 0)
        check_elements("faces", mesh.frustum(m), [np.asarray(t) for t in f], vin, vamb, marg)
        check_elements("edges", mesh.frustum(m, primitives="edges"), list(edges), vin, vamb, marg)
        check_elements("polygons", mesh.frustum(m, primitives="polygons"), [np.asarray(t) for t in f], vin, vamb, marg)
        counts.append(len(expect))
    # the cameras saw part of the mesh, not all of it and not nothing
    assert sum(0 < c < len(vv) for c in counts) >= 4, counts


def test_frustum_quads_polygons():
    v, f = quad_grid_arrays()
    mesh = proxima.Mesh(v, f)
    vv = v.astype(np.float64)
    for m in cameras(7, n=4):
        vin, vamb, marg = inside_vertices(m, vv)
        for prim in ("faces", "polygons"):
            check_elements(prim, mesh.frustum(m, primitives=prim), list(f), vin, vamb, marg)


def test_frustum_sees_nothing_and_everything(icosphere):
    behind = o.perspective(60, 1, 0.1, 10) @ o.look_at([0, 0, 5], [0, 0, 10], [0, 1, 0])
    for prim in ("faces", "vertices", "edges", "polygons"):
        got = icosphere.frustum(behind, primitives=prim)
        assert got.dtype == np.int64 and got.shape == (0,)
    whole = o.perspective(60, 1, 0.1, 100) @ o.look_at([0, 0, 10], [0, 0, 0], [0, 1, 0])
    assert icosphere.frustum(whole).tolist() == list(range(len(icosphere)))
    assert icosphere.frustum(whole, primitives="vertices").tolist() == list(range(len(icosphere.vertices)))


def test_frustum_face_spanning_without_vertex_inside():
    """A big triangle whose vertices are all outside but which crosses the
    view: it shares points with the frustum, so it is returned."""
    v = np.array([[-100, -100, 0], [100, -100, 0], [0, 100, 0]], np.float32)
    mesh = proxima.Mesh(v, [[0, 1, 2]])
    m = o.perspective(40, 1, 1, 10) @ o.look_at([0, 0, 5], [0, 0, 0], [0, 1, 0])
    assert mesh.frustum(m, primitives="vertices").tolist() == []
    assert mesh.frustum(m).tolist() == [0]
    assert mesh.frustum(m, primitives="edges").tolist() == []

"""The stub's contract: dtypes, shapes, memory layouts, empty input, threads,
lazily built structures, and the GIL released during batch calls."""

import threading
import time

import numpy as np
import pytest

import proxima
from conftest import data_path, query_points

PRIMS = ["faces", "vertices", "edges", "polygons"]


@pytest.fixture(scope="module")
def ico():
    return proxima.noisy_icosphere(6)


@pytest.fixture(scope="module")
def pts(ico):
    return query_points(ico.vertices, 300, seed=2)


def all_calls(mesh, p, threads=None):
    """Every batch query on points p, as a dict name -> tuple of arrays."""
    out = {}
    for prim in PRIMS:
        out[f"closest_{prim}"] = mesh.closest_points(p, primitives=prim, threads=threads)
        out[f"knn_{prim}"] = mesh.k_nearest(p, 3, primitives=prim, threads=threads)
    out["sd"] = (mesh.signed_distance(p, threads=threads),)
    out["sd_pn"] = (mesh.signed_distance(p, sign="pseudonormal", threads=threads),)
    out["wn"] = (mesh.winding_number(p, threads=threads),)
    out["contains"] = (mesh.contains(p, threads=threads),)
    d = np.asarray(p)[::-1].copy() - np.asarray(p)
    d[np.all(d == 0, axis=1)] = 1.0
    out["rays"] = mesh.cast_rays(p, d, threads=threads)
    out["rays_any"] = mesh.cast_rays(p, d, any_hit=True, threads=threads)
    return out


def check_types(res, n):
    for prim in PRIMS:
        c, d, i = res[f"closest_{prim}"]
        assert (c.dtype, c.shape) == (np.float64, (n, 3))
        assert (d.dtype, d.shape) == (np.float64, (n,))
        assert (i.dtype, i.shape) == (np.int64, (n,))
        d, i = res[f"knn_{prim}"]
        assert (d.dtype, d.shape) == (np.float64, (n, 3)) and (i.dtype, i.shape) == (np.int64, (n, 3))
    for k in ("sd", "sd_pn", "wn"):
        assert (res[k][0].dtype, res[k][0].shape) == (np.float64, (n,)), k
    assert (res["contains"][0].dtype, res["contains"][0].shape) == (np.bool_, (n,))
    for k in ("rays", "rays_any"):
        t, i = res[k]
        assert (t.dtype, t.shape, i.dtype, i.shape) == (np.float64, (n,), np.int64, (n,)), k


def assert_same(a, b, what):
    assert a.keys() == b.keys()
    for k in a:
        for x, y in zip(a[k], b[k]):
            np.testing.assert_array_equal(x, y, err_msg=f"{what}: {k}")


def test_dtypes_and_shapes(ico, pts):
    for dtype in (np.float32, np.float64):
        check_types(all_calls(ico, pts.astype(dtype)), len(pts))


def test_layouts_give_the_same_answers(ico, pts):
    base = all_calls(ico, np.ascontiguousarray(pts, dtype=np.float64))
    f32 = pts.astype(np.float32)
    doubled = np.empty((2 * len(pts), 3))
    doubled[::2] = pts
    variants = {
        "float32 C": np.ascontiguousarray(f32),
        "float64 F": np.asfortranarray(pts),
        "float32 F": np.asfortranarray(f32),
        "row slice": doubled[::2],  # every other row of a bigger array: pts, not contiguous
        "column slice": np.concatenate([pts, np.zeros_like(pts)], axis=1)[:, :3],
        "list": pts.tolist(),
    }
    assert not variants["row slice"].flags.c_contiguous and not variants["column slice"].flags.c_contiguous
    for name, p in variants.items():
        assert_same(base, all_calls(ico, p), name)
    # negative strides: the answers of the reversed points are the reversed answers
    rev = all_calls(ico, pts[::-1])
    assert_same({k: tuple(x[::-1] for x in v) for k, v in base.items()}, rev, "negative stride")


def test_threads_one_equals_default(ico):
    p = query_points(ico.vertices, 5000, seed=3)
    assert_same(all_calls(ico, p, threads=1), all_calls(ico, p), "threads=1 vs None")
    assert_same(all_calls(ico, p, threads=2), all_calls(ico, p), "threads=2 vs None")
    a, b = ico.voxelize(20, threads=1), ico.voxelize(20)
    np.testing.assert_array_equal(a.cells, b.cells)


def test_empty_input(ico):
    for dtype in (np.float32, np.float64):
        e = np.zeros((0, 3), dtype=dtype)
        res = all_calls(ico, e)
        check_types(res, 0)
    # an empty list of rows is not (0, 3): accepted only as a proper (0, 3) array
    t, i = ico.cast_rays(np.zeros((0, 3)), np.zeros((0, 3)))
    assert t.shape == (0,) and i.shape == (0,)


def test_mesh_arrays_contract(ico):
    v, f = ico.vertices, ico.faces
    assert v.dtype == np.float32 and v.shape == (len(v), 3)
    assert f.dtype == np.int64 and f.shape == (20 * 6**2, 3)
    assert len(ico) == len(f)
    b = ico.bounds
    assert b.dtype == np.float64 and b.shape == (2, 3)
    np.testing.assert_array_equal(b, [v.min(0), v.max(0)])
    # copies: writing into them does not change the mesh
    v[:] = 0
    assert np.any(ico.vertices != 0)
    assert isinstance(proxima.__version__, str) and proxima.__version__


def test_sampling_contract(ico):
    a = ico.sample_near_surface(1000, seed=3)
    assert a.dtype == np.float32 and a.shape == (1000, 3)
    np.testing.assert_array_equal(a, ico.sample_near_surface(1000, seed=3))
    assert not np.array_equal(a, ico.sample_near_surface(1000, seed=4))
    # near the surface: distances about sigma * diagonal (gaussian per axis)
    diag = np.linalg.norm(ico.bounds[1] - ico.bounds[0])
    _, d, _ = ico.closest_points(a)
    assert np.median(d) < 0.05 * diag
    u = ico.sample_uniform(2000, seed=1)
    assert u.dtype == np.float32 and u.shape == (2000, 3)
    lo, hi = ico.bounds
    size = hi - lo
    assert np.all(u >= lo - 0.1 * size - 1e-6) and np.all(u <= hi + 0.1 * size + 1e-6)
    assert np.all(u.min(0) < lo) and np.all(u.max(0) > hi)  # the 10% margin is used
    assert ico.sample_near_surface(0).shape == (0, 3)


def test_structures_are_built_once():
    """Each structure is built by the first call that needs it and kept: the
    list of built structures grows only when a call needs a new one, and
    signed distances reuse the faces' tree of closest_points."""
    mesh = proxima.noisy_icosphere(16)  # a fresh Mesh: nothing built yet
    p = mesh.sample_near_surface(2000, seed=1)
    d = np.random.default_rng(0).normal(size=p.shape)
    assert mesh.built_structures() == []
    steps = [
        (lambda: mesh.closest_points(p), ["faces"]),
        (lambda: mesh.closest_points(p), ["faces"]),
        (lambda: mesh.signed_distance(p), ["faces", "winding"]),
        (lambda: mesh.winding_number(p), ["faces", "winding"]),
        (lambda: mesh.contains(p), ["faces", "winding"]),
        (lambda: mesh.closest_points(p, primitives="edges"), ["edges", "faces", "winding"]),
        (lambda: mesh.signed_distance(p, sign="pseudonormal"), ["edges", "faces", "winding", "pseudonormal"]),
        (lambda: mesh.cast_rays(p, d), ["edges", "faces", "winding", "pseudonormal", "rays"]),
        (lambda: mesh.cast_rays(p, d, any_hit=True), ["edges", "faces", "winding", "pseudonormal", "rays"]),
        (lambda: mesh.k_nearest(p, 3, primitives="vertices"), ["vertices", "edges", "faces", "winding", "pseudonormal", "rays"]),
    ]
    for call, built in steps:
        call()
        assert mesh.built_structures() == built


def test_structures_built_by_concurrent_threads_once():
    """Python threads asking for the same structure at once share one build
    and get the same answers."""
    import concurrent.futures

    mesh = proxima.noisy_icosphere(60)
    p = mesh.sample_near_surface(20_000, seed=2)
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        answers = list(pool.map(lambda _: mesh.signed_distance(p, threads=1), range(4)))
    for a in answers[1:]:
        np.testing.assert_array_equal(a, answers[0])
    assert mesh.built_structures() == ["faces", "winding"]


def test_gil_released_during_closest_points():
    """A Python thread keeps running while closest_points works on ~1M points
    with threads=1 in another thread."""
    mesh = proxima.noisy_icosphere(40)
    p = np.random.default_rng(0).normal(size=(1_000_000, 3)).astype(np.float32)
    mesh.closest_points(p[:10])  # build the tree first: time the queries only
    span = {}
    result = {}

    def work():
        span["start"] = time.perf_counter()
        result["out"] = mesh.closest_points(p, threads=1)
        span["end"] = time.perf_counter()

    stamps = []
    t = threading.Thread(target=work)
    t.start()
    count = 0
    while t.is_alive():
        count += 1
        if count % 1000 == 0:
            stamps.append(time.perf_counter())
    t.join()
    assert result["out"][1].shape == (1_000_000,)
    duration = span["end"] - span["start"]
    assert duration > 0.05, f"the call took only {duration:.3f}s: too short to test"
    inside = np.array([s for s in stamps if span["start"] < s < span["end"]])
    # the main thread ran throughout the call: its stamps fall in most tenths of it
    bins = set(((inside - span["start"]) / duration * 10).astype(int).tolist())
    assert len(bins) >= 7, f"main thread progressed in only {len(bins)} tenths of a {duration:.2f}s call"

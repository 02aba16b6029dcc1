"""Shared fixtures of the proxima Python tests: meshes, data directory, helpers."""

import os
from pathlib import Path

import numpy as np
import pytest

import proxima

REPO_ROOT = Path(__file__).resolve().parents[3]


def data_dir():
    """The shared real meshes: $PROXIMA_DATA_DIR, else ../shared/data beside the
    repository; None when absent."""
    env = os.environ.get("PROXIMA_DATA_DIR")
    candidate = Path(env) if env else REPO_ROOT.parent / "shared" / "data"
    return candidate if candidate.is_dir() else None


DATA = data_dir()
DATA_NOTE = (
    f"real meshes from {DATA}"
    if DATA
    else "real meshes NOT FOUND (../shared/data beside the repository, or set PROXIMA_DATA_DIR): "
    "the tests on them are skipped"
)


def pytest_report_header(config):
    return f"proxima {getattr(proxima, '__version__', '?')} from {Path(proxima.__file__).parent}; {DATA_NOTE}"


def pytest_terminal_summary(terminalreporter):
    if DATA is None:
        terminalreporter.write_line("NOTE: " + DATA_NOTE, yellow=True)


def data_path(name):
    """The path of a shared mesh, skipping the test (with a note) when absent."""
    if DATA is None:
        pytest.skip(DATA_NOTE)
    path = DATA / name
    if not path.exists():
        pytest.skip(f"{name} not in {DATA}")
    return path


_LOADED = {}


def load_shared(name):
    """proxima.load of a shared mesh, cached for the session (read only!)."""
    path = data_path(name)
    if name not in _LOADED:
        _LOADED[name] = proxima.load(path)
    return _LOADED[name]


# --- generated meshes --------------------------------------------------------------


def random_soup(n_tris, seed):
    """Independent random triangles in the unit cube: (V, 3) float32, (F, 3)."""
    rng = np.random.default_rng(seed)
    v = rng.random((3 * n_tris, 3)).astype(np.float32)
    f = np.arange(3 * n_tris, dtype=np.int64).reshape(-1, 3)
    return v, f


def cube_arrays():
    """The unit cube [0, 1]^3 as 12 outward triangles."""
    v = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]],
        dtype=np.float32,
    )
    quads = cube_quads()
    f = np.array([[q[0], q[1], q[2]] for q in quads] + [[q[0], q[2], q[3]] for q in quads], dtype=np.int64)
    return v, f


def cube_quads():
    """The unit cube's 6 outward quads (indices into cube_arrays' vertices)."""
    return np.array(
        [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 4, 7, 3]], dtype=np.int64
    )


def quad_grid_arrays(n=6, seed=3):
    """A closed box of planar convex quads: each side of a box split into
    n x n quads, vertices of each side shared (so the mesh is closed), plus a
    random float32 scaling and offset (planarity is kept: each side is axis
    aligned). Returns (V, 3) float32 and (F, 4) int64."""
    rng = np.random.default_rng(seed)
    scale = (0.5 + rng.random(3)).astype(np.float64)
    offset = rng.random(3) - 0.5
    verts = {}
    faces = []

    def vid(p):
        key = tuple(int(x) for x in p)
        if key not in verts:
            verts[key] = len(verts)
        return verts[key]

    for axis in range(3):
        u, w = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, n):
            for i in range(n):
                for j in range(n):
                    corners = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0, 0, 0]
                        p[axis], p[u], p[w] = side, i + di, j + dj
                        corners.append(vid(p))
                    if side == 0:
                        corners = corners[::-1]
                    faces.append(corners)
    v = np.array(sorted(verts, key=verts.get), dtype=np.float64) / n
    v = (v * scale + offset).astype(np.float32)
    return v, np.array(faces, dtype=np.int64)


@pytest.fixture(scope="session")
def icosphere():
    return proxima.noisy_icosphere(4)


@pytest.fixture(scope="session")
def cube():
    v, f = cube_arrays()
    return proxima.Mesh(v, f)


def query_points(vertices, n, seed, spread=0.3):
    """Points around a mesh: a third near vertices, a third uniform in the
    enlarged box, a third far-ish; float32-rounded, as float64."""
    rng = np.random.default_rng(seed)
    v = np.asarray(vertices, dtype=np.float64)
    lo, hi = v.min(0), v.max(0)
    size = np.max(hi - lo)
    a = v[rng.integers(0, len(v), n // 3)] + rng.normal(0, 0.05 * size, (n // 3, 3))
    b = lo - spread * size + rng.random((n // 3, 3)) * (hi - lo + 2 * spread * size)
    c = (lo + hi) / 2 + rng.normal(0, 2 * size, (n - 2 * (n // 3), 3))
    return np.concatenate([a, b, c]).astype(np.float32).astype(np.float64)


def assert_not_panic(exc):
    """A PanicException (pyo3_runtime) derives from BaseException: make sure an
    exception caught as BaseException is not one."""
    name = type(exc).__name__
    assert "Panic" not in name, f"Rust panic reached Python: {name}: {exc}"
    assert isinstance(exc, Exception), f"{name} is not an Exception: {exc}"


def pytest_configure(config):
    # `-m ray` / `-m "not ray"` select the tests that start a local Ray instance.
    config.addinivalue_line("markers", "ray: starts a local Ray instance (proxima.dataset on Ray)")


def pytest_collection_modifyitems(config, items):
    """The autograd adapters' tests run last: importing JAX starts threads,
    and the Ray tests fork worker processes, which JAX warns may deadlock
    once its threads exist."""
    items.sort(key=lambda item: item.fspath.basename == "test_autodiff.py")

"""Bad input: a ValueError (OSError for I/O) naming the argument, never a Rust
panic (pyo3_runtime.PanicException derives from BaseException)."""

import gzip

import numpy as np
import pytest

import proxima
from conftest import assert_not_panic, cube_arrays

V, F = cube_arrays()
P = np.array([[0.5, 0.5, 2.0], [0.1, 0.2, 0.3]])
NAN = np.array([[0.0, np.nan, 0.0]])
INF = np.array([[np.inf, 0.0, 0.0]])


def mesh():
    return proxima.Mesh(V, F)


def perspective():
    import oracles as o

    return o.perspective(60, 1, 0.1, 10) @ o.look_at([0, 0, 3], [0, 0, 0], [0, 1, 0])


M = mesh()
GOOD_VP = perspective()

# (id, callable, expected exception type, words of which the message must contain one)
CASES = [
    # --- Mesh construction
    ("vertices (N,2)", lambda: proxima.Mesh(V[:, :2], F), ValueError, ["vertices"]),
    ("vertices (3,)", lambda: proxima.Mesh(V[0], F), ValueError, ["vertices"]),
    ("vertices 3-D", lambda: proxima.Mesh(V[None], F), ValueError, ["vertices"]),
    ("vertices strings", lambda: proxima.Mesh(V.astype(str), F), ValueError, ["vertices"]),
    ("vertices objects", lambda: proxima.Mesh(np.array([[0, 0, None]] * 8, dtype=object), F), ValueError, ["vertices"]),
    ("vertices complex", lambda: proxima.Mesh(V.astype(np.complex128), F), ValueError, ["vertices"]),
    ("vertices NaN", lambda: proxima.Mesh(np.where(np.arange(24).reshape(8, 3) == 4, np.nan, V), F), ValueError, ["vertices"]),
    ("vertices inf", lambda: proxima.Mesh(np.where(np.arange(24).reshape(8, 3) == 4, np.inf, V), F), ValueError, ["vertices"]),
    ("faces out of range", lambda: proxima.Mesh(V, np.where(F == 7, 8, F)), ValueError, ["faces", "index"]),
    ("faces huge index", lambda: proxima.Mesh(V, np.where(F == 7, 2**40, F)), ValueError, ["faces", "index"]),
    ("faces negative", lambda: proxima.Mesh(V, np.where(F == 7, -1, F)), ValueError, ["faces", "index"]),
    ("faces of 2 vertices", lambda: proxima.Mesh(V, F[:, :2]), ValueError, ["faces"]),
    ("faces list with a 2-gon", lambda: proxima.Mesh(V, [[0, 1, 2], [0, 1]]), ValueError, ["faces"]),
    ("faces list negative", lambda: proxima.Mesh(V, [[0, 1, 2, 3], [0, -1, 2]]), ValueError, ["faces", "index"]),
    ("faces float", lambda: proxima.Mesh(V, F.astype(np.float64) + 0.5), ValueError, ["faces"]),
    ("faces strings", lambda: proxima.Mesh(V, F.astype(str)), ValueError, ["faces"]),
    ("faces 3-D", lambda: proxima.Mesh(V, F[None]), ValueError, ["faces"]),
    ("faces (F,)", lambda: proxima.Mesh(V, F[0]), ValueError, ["faces"]),
    # --- points of every batch query
    *[
        (f"{name} {what}", (lambda fn=fn, p=p: fn(p)), ValueError, ["points"])
        for name, fn in [
            ("closest_points", lambda p: M.closest_points(p)),
            ("closest_points edges", lambda p: M.closest_points(p, primitives="edges")),
            ("k_nearest", lambda p: M.k_nearest(p, 2)),
            ("signed_distance", lambda p: M.signed_distance(p)),
            ("winding_number", lambda p: M.winding_number(p)),
            ("contains", lambda p: M.contains(p)),
        ]
        for what, p in [
            ("(N,2)", P[:, :2]),
            ("(3,)", P[0]),
            ("3-D", P[None]),
            ("(N,4)", np.ones((2, 4))),
            ("strings", P.astype(str)),
            ("objects", np.array([[0.0, None, 1.0]], dtype=object)),
            ("complex", P.astype(np.complex64)),
            ("NaN", NAN),
            ("inf", INF),
        ]
    ],
    # --- other arguments of the queries
    ("k=0", lambda: M.k_nearest(P, 0), ValueError, ["k"]),
    ("k=-1", lambda: M.k_nearest(P, -1), ValueError, ["k"]),
    ("threads=0", lambda: M.closest_points(P, threads=0), ValueError, ["threads"]),
    ("threads=-2", lambda: M.closest_points(P, threads=-2), ValueError, ["threads"]),
    ("threads=0 sd", lambda: M.signed_distance(P, threads=0), ValueError, ["threads"]),
    ("threads=0 rays", lambda: M.cast_rays(P, P, threads=0), ValueError, ["threads"]),
    ("threads=0 voxelize", lambda: M.voxelize(4, threads=0), ValueError, ["threads"]),
    ("primitives unknown", lambda: M.closest_points(P, primitives="triangles"), ValueError, ["primitives"]),
    ("primitives unknown knn", lambda: M.k_nearest(P, 2, primitives="face"), ValueError, ["primitives"]),
    ("primitives unknown frustum", lambda: M.frustum(GOOD_VP, primitives="cells"), ValueError, ["primitives"]),
    (
        "return_barycentric of edges",
        lambda: M.closest_points(P, primitives="edges", return_barycentric=True),
        ValueError,
        ["primitives", "faces"],
    ),
    ("gradient of a NaN point", lambda: M.signed_distance([[np.nan, 0, 0]], return_gradient=True), ValueError, ["points[0]"]),
    ("sign unknown", lambda: M.signed_distance(P, sign="normals"), ValueError, ["sign"]),
    # --- rays
    ("zero direction", lambda: M.cast_rays(P, np.array([[0.0, 0, 1], [0, 0, 0]])), ValueError, ["direction"]),
    ("NaN direction", lambda: M.cast_rays(P, np.array([[0.0, 0, 1], [0, np.nan, 1]])), ValueError, ["direction"]),
    ("inf origin", lambda: M.cast_rays(np.array([[0.0, 0, 1], [0, np.inf, 1]]), P), ValueError, ["origin"]),
    ("rays count mismatch", lambda: M.cast_rays(P, P[:1]), ValueError, ["origins", "directions"]),
    ("rays (N,2) origins", lambda: M.cast_rays(P[:, :2], P), ValueError, ["origins"]),
    ("rays (N,2) directions", lambda: M.cast_rays(P, P[:, :2]), ValueError, ["directions"]),
    ("rays complex", lambda: M.cast_rays(P, P.astype(complex)), ValueError, ["directions"]),
    # --- voxelize
    ("resolution 0", lambda: M.voxelize(0), ValueError, ["resolution"]),
    ("resolution -1", lambda: M.voxelize(-1), ValueError, ["resolution"]),
    ("resolution huge", lambda: M.voxelize(2_000_000), ValueError, ["resolution"]),
    # --- frustum
    ("frustum NaN", lambda: M.frustum(np.where(np.eye(4) == 1, np.nan, GOOD_VP)), ValueError, ["view_projection"]),
    ("frustum (3,3)", lambda: M.frustum(GOOD_VP[:3, :3]), ValueError, ["view_projection"]),
    ("frustum (16,)", lambda: M.frustum(GOOD_VP.ravel()), ValueError, ["view_projection"]),
    ("frustum (4,4,1)", lambda: M.frustum(GOOD_VP[..., None]), ValueError, ["view_projection"]),
    ("frustum singular", lambda: M.frustum(np.zeros((4, 4))), ValueError, ["view_projection"]),
    ("frustum strings", lambda: M.frustum(GOOD_VP.astype(str)), ValueError, ["view_projection"]),
    # --- traverse
    ("traverse cell 0", lambda: proxima.traverse([0, 0, 0], [1, 0, 0], 0.0, 3), ValueError, ["cell_size"]),
    ("traverse cell <0", lambda: proxima.traverse([0, 0, 0], [1, 0, 0], -1.0, 3), ValueError, ["cell_size"]),
    ("traverse cell3 <0", lambda: proxima.traverse([0, 0, 0], [1, 0, 0], [1, -1, 1], 3), ValueError, ["cell_size"]),
    ("traverse cell NaN", lambda: proxima.traverse([0, 0, 0], [1, 0, 0], np.nan, 3), ValueError, ["cell_size"]),
    ("traverse cell (2,)", lambda: proxima.traverse([0, 0, 0], [1, 0, 0], [1, 1], 3), ValueError, ["cell_size"]),
    ("traverse zero dir", lambda: proxima.traverse([0, 0, 0], [0, 0, 0], 1.0, 3), ValueError, ["direction"]),
    ("traverse NaN dir", lambda: proxima.traverse([0, 0, 0], [np.nan, 0, 0], 1.0, 3), ValueError, ["direction"]),
    ("traverse inf origin", lambda: proxima.traverse([np.inf, 0, 0], [1, 0, 0], 1.0, 3), ValueError, ["origin"]),
    ("traverse origin (2,)", lambda: proxima.traverse([0, 0], [1, 0, 0], 1.0, 3), ValueError, ["origin"]),
    ("traverse steps<0", lambda: proxima.traverse([0, 0, 0], [1, 0, 0], 1.0, -1), ValueError, ["steps"]),
    # --- sampling and generation
    ("noisy_icosphere 0", lambda: proxima.noisy_icosphere(0), ValueError, ["frequency"]),
    ("sample sigma<0", lambda: M.sample_near_surface(10, sigma=-1.0), ValueError, ["sigma"]),
    # --- training samples and grids (the recipe of proxima sdf and proxima.dataset)
    ("training_samples near_sigma<0", lambda: M.training_samples(10, -1.0), ValueError, ["near_sigma"]),
    ("training_samples near_sigma NaN", lambda: M.training_samples(10, np.nan), ValueError, ["near_sigma"]),
    ("training_samples near_sigma 1e30", lambda: M.training_samples(10, 1e30), ValueError, ["near_sigma"]),
    ("training_samples uniform_fraction>1", lambda: M.training_samples(10, 0.01, uniform_fraction=1.5), ValueError, ["uniform_fraction"]),
    ("training_samples cube 0", lambda: M.training_samples(10, 0.01, cube=0.0), ValueError, ["cube"]),
    ("training_samples cube NaN", lambda: M.training_samples(10, 0.01, cube=np.nan), ValueError, ["cube"]),
    ("training_samples cube 1e30", lambda: M.training_samples(10, 0.01, uniform_fraction=1.0, cube=1e30), ValueError, ["cube"]),
    ("training_samples n beyond the budget", lambda: M.training_samples(2**62, 0.01), ValueError, ["n 4611686018427387904: needs about"]),
    ("training_samples sign", lambda: M.training_samples(10, 0.01, sign="up"), ValueError, ["sign"]),
    ("sdf_grid resolution 0", lambda: M.sdf_grid(0), ValueError, ["resolution"]),
    ("sdf_grid resolution beyond the budget", lambda: M.sdf_grid(100_000), ValueError, ["resolution 100000: needs about"]),
    ("sdf_grid cube<0", lambda: M.sdf_grid(4, cube=-1.0), ValueError, ["cube"]),
    ("training_sample_counts fraction<0", lambda: proxima.training_sample_counts(10, -0.1), ValueError, ["uniform_fraction"]),
    ("check_fits beyond the budget", lambda: proxima.check_fits("things", 5, 2**62, 8), ValueError, ["things 5: needs about"]),
]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_bad_input(case):
    _, fn, exc_type, words = case
    try:
        fn()
    except BaseException as e:  # noqa: B036 - a PanicException is a BaseException
        assert_not_panic(e)
        assert isinstance(e, exc_type), f"{type(e).__name__} instead of {exc_type}: {e}"
        msg = str(e).lower()
        assert any(w.lower() in msg for w in words), f"message does not name {words}: {e}"
    else:
        pytest.fail("no error raised")


def test_voxelize_memory_budget_from_environment(monkeypatch):
    monkeypatch.setenv("PROXIMA_MEMORY_BUDGET", "1000000")
    with pytest.raises(ValueError, match="budget"):
        M.voxelize(400)
    monkeypatch.delenv("PROXIMA_MEMORY_BUDGET")
    assert len(M.voxelize(400)) > 0


def test_limits_are_the_ones_calls_enforce(monkeypatch):
    """memory_budget() and max_threads() report the limits the calls apply."""
    import os

    cap = proxima.max_threads()
    assert cap == max(8, 4 * (os.cpu_count() or 1))
    M.closest_points(P, threads=cap)
    with pytest.raises(ValueError, match="threads"):
        M.closest_points(P, threads=cap + 1)
    monkeypatch.setenv("PROXIMA_MEMORY_BUDGET", "64K")
    assert proxima.memory_budget() == 64 << 10
    with pytest.raises(ValueError, match="budget"):
        M.sample_uniform(64 << 10)  # 12 bytes a point: past 64 KiB
    with pytest.raises(ValueError, match=r"^n 65536: needs about 768.0 KiB .*memory budget of 64.0 KiB"):
        M.sample_uniform(64 << 10)
    proxima.check_fits("n", 1, 64 << 10, 1)  # exactly the budget fits
    with pytest.raises(ValueError, match=r"^n 1: needs about 64.0 KiB \(1 × 65537 = 65537 bytes\)"):
        proxima.check_fits("n", 1, 1, (64 << 10) + 1)
    monkeypatch.setenv("PROXIMA_MEMORY_BUDGET", "64 apples")
    with pytest.raises(ValueError, match="PROXIMA_MEMORY_BUDGET: '64 apples' is not a number"):
        proxima.check_fits("n", 1, 1, 1)
    with pytest.raises(ValueError, match="PROXIMA_MEMORY_BUDGET"):
        proxima.memory_budget()
    monkeypatch.delenv("PROXIMA_MEMORY_BUDGET")
    assert proxima.memory_budget() > 64 << 20


def test_nothing_is_built_wrong_after_errors():
    """A mesh that refused bad input still answers."""
    m = mesh()
    for bad in (NAN, P[:, :2]):
        with pytest.raises(ValueError):
            m.closest_points(bad)
    _, d, _ = m.closest_points(P)
    np.testing.assert_allclose(d, [1.0, 0.1], rtol=1e-6)


# --- files -----------------------------------------------------------------------------

CUBE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def load_error(path):
    try:
        proxima.load(path)
    except BaseException as e:  # noqa: B036
        assert_not_panic(e)
        return e
    pytest.fail(f"load({path}) raised nothing")


def test_load_good_obj(tmp_path):
    p = tmp_path / "tet.obj"
    p.write_text(CUBE_OBJ)
    m = proxima.load(p)
    assert m.faces.shape == (4, 3) and m.vertices.shape == (4, 3)
    g = tmp_path / "tet.obj.gz"
    g.write_bytes(gzip.compress(CUBE_OBJ.encode()))
    np.testing.assert_array_equal(proxima.load(str(g)).faces, m.faces)


def test_load_missing_file(tmp_path):
    p = tmp_path / "missing.obj"
    e = load_error(p)
    assert isinstance(e, OSError), repr(e)
    assert "missing.obj" in str(e)


def test_load_directory(tmp_path):
    d = tmp_path / "dir.obj"
    d.mkdir()
    e = load_error(d)
    assert isinstance(e, OSError), repr(e)


@pytest.mark.parametrize(
    "name, content",
    [
        ("truncated.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 "),
        ("badnumber.obj", "v 0 0 zero\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        ("badindex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
        ("truncated.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n"),
        ("truncated_binary.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\x00\x00"),
        ("truncated.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n"),
        ("truncated.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"),
        ("empty.obj", ""),
        ("empty.ply", ""),
        ("empty.off", ""),
        ("empty.stl", ""),
        ("binary.obj", "\x00\x01\x02\x03garbage"),
    ],
)
def test_load_malformed(tmp_path, name, content):
    p = tmp_path / name
    p.write_bytes(content.encode("latin-1"))
    e = load_error(p)
    assert isinstance(e, ValueError), f"{type(e).__name__}: {e}"
    assert name in str(e), f"message does not name the file: {e}"


def test_load_unknown_extension(tmp_path):
    p = tmp_path / "mesh.xyz"
    p.write_text(CUBE_OBJ)
    e = load_error(p)
    assert isinstance(e, ValueError), f"{type(e).__name__}: {e}"
    assert "mesh.xyz" in str(e)


def test_load_corrupt_gzip(tmp_path):
    p = tmp_path / "bad.obj.gz"
    p.write_bytes(gzip.compress(CUBE_OBJ.encode())[:-12] + b"\xff" * 4)
    e = load_error(p)
    assert isinstance(e, (OSError, ValueError)), f"{type(e).__name__}: {e}"
    assert "bad.obj.gz" in str(e)

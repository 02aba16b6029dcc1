"""Mesh construction, from_trimesh, and load() on every shared mesh."""

import gzip
import io

import numpy as np
import pytest

import proxima
from conftest import cube_arrays, data_path, quad_grid_arrays

# Independent figures from shared/data/README.md (measured there by another reader):
# vertices as stored, faces as stored (polygons counted once), triangles after
# fan triangulation, bounding box.
README = {
    "bunny-npm.obj": (1839, 3674, 3674, (-4.95847, -0.003149, -3.72983), (4.94885, 9.65475, 3.81064)),
    "spot_quadrangulated.obj": (2930, 2928, 5856, (-0.471552, -0.736784, -0.668909), (0.471552, 0.953646, 1.049)),
    "spot_triangulated.obj": (2930, 5856, 5856, (-0.471552, -0.736784, -0.668909), (0.471552, 0.953646, 1.049)),
    "teapot.obj": (3644, 6320, 6320, (-3, 0, -2), (3.434, 3.15, 2)),
    "fandisk.obj": (6475, 12946, 12946, (0, 12.6055, -2.68026), (4.8279, 17.85, 0)),
    "blade.off": (8231, 16222, 16222, (-5.98992, 12.9959, 1.43743), (4.0083, 142.182, 2.08567)),
    "rocker-arm.obj": (10044, 20088, 20088, (-0.151733, -0.257456, -0.5), (0.151733, 0.257456, 0.5)),
    "beast.obj": (32311, 32364, 64618, (-136.888, -0.869426, -29.6748), (136.888, 251.326, 86.8523)),
    "stanford-bunny.obj": (35947, 69451, 69451, (-0.09469, 0.032987, -0.061874), (0.061009, 0.187321, 0.0588)),
    "nefertiti.obj": (49971, 99938, 99938, (-119.323, -181.293, -247.268), (119.363, 181.241, 247.337)),
    "dragon_vrip_res2.ply": (
        100250, 202520, 202520, (-0.108188, 0.0527392, -0.0503454), (0.0964062, 0.197139, 0.0411367)),
    "dragon_vrip.ply.gz": (
        437645, 871414, 871414, (-0.108324, 0.0527295, -0.0504143), (0.0965662, 0.197173, 0.0412075)),
}


def face_sizes(mesh):
    faces = mesh.faces
    if isinstance(faces, np.ndarray):
        assert faces.dtype == np.int64 and faces.ndim == 2
        return np.full(len(faces), faces.shape[1])
    assert isinstance(faces, list) and all(f.dtype == np.int64 and f.ndim == 1 for f in faces)
    return np.array([len(f) for f in faces])


@pytest.mark.parametrize("name", list(README))
def test_load_shared_mesh(name):
    path = data_path(name)
    mesh = proxima.load(path)
    nv, nf, ntri, lo, hi = README[name]
    sizes = face_sizes(mesh)
    assert len(mesh) == nf == len(sizes)
    assert int(np.sum(sizes - 2)) == ntri
    assert mesh.vertices.shape == (nv, 3)
    np.testing.assert_allclose(mesh.bounds, [lo, hi], rtol=1e-5, atol=1e-5)
    if name == "beast.obj":
        assert np.bincount(sizes).tolist()[3:] == [124, 32228, 10, 2]
    if name == "spot_quadrangulated.obj":
        assert isinstance(mesh.faces, np.ndarray) and mesh.faces.shape == (2928, 4)


def trimesh_load(path):
    trimesh = pytest.importorskip("trimesh")
    if path.suffix == ".obj":
        # without materials (they need Pillow) and in the file's vertex order
        from trimesh.exchange.obj import load_obj

        with open(path, "rb") as fh:
            kw = load_obj(fh, skip_materials=True, maintain_order=True)
        if "geometry" in kw:
            (kw,) = kw["geometry"].values()
        return trimesh.Trimesh(vertices=kw["vertices"], faces=kw["faces"], process=False)
    if path.name.endswith(".gz"):
        data = gzip.decompress(path.read_bytes())
        kind = path.name[:-3].rsplit(".", 1)[1]
        return trimesh.load(io.BytesIO(data), file_type=kind, process=False, force="mesh")
    return trimesh.load(path, process=False, force="mesh")


# trimesh's loader reads these differently (it is not the oracle there):
TRIMESH_DIFFERS = {}


@pytest.mark.parametrize("name", [n for n in README if n != "dragon_vrip.ply.gz"])
def test_load_face_counts_match_trimesh(name):
    path = data_path(name)
    tm = trimesh_load(path)
    mesh = proxima.load(path)
    ntri = int(np.sum(face_sizes(mesh) - 2))
    if name in TRIMESH_DIFFERS:
        pytest.skip(TRIMESH_DIFFERS[name])
    assert len(tm.faces) == ntri, f"trimesh {len(tm.faces)} triangles, proxima {ntri}"
    # where trimesh keeps the stored vertices, the geometry is the same
    if len(tm.vertices) == len(mesh.vertices):
        np.testing.assert_allclose(mesh.vertices, tm.vertices, rtol=1e-6, atol=1e-6)
        if isinstance(mesh.faces, np.ndarray) and mesh.faces.shape[1] == 3:
            np.testing.assert_array_equal(mesh.faces, tm.faces)
        # (polygons: trimesh picks its own diagonals, so only the counts compare)
    else:
        print(f"{name}: trimesh has {len(tm.vertices)} vertices, proxima {len(mesh.vertices)}")


def test_mesh_round_trip_triangles():
    v, f = cube_arrays()
    for vt in (np.float32, np.float64):
        for ft in (np.int64, np.int32, np.uint32, np.int16):
            m = proxima.Mesh(v.astype(vt), f.astype(ft))
            assert m.vertices.dtype == np.float32
            np.testing.assert_array_equal(m.vertices, v)
            assert m.faces.dtype == np.int64 and m.faces.shape == (12, 3)
            np.testing.assert_array_equal(m.faces, f)
    # nested lists work too
    m = proxima.Mesh(v.tolist(), f.tolist())
    np.testing.assert_array_equal(m.faces, f)
    # float64 vertices are stored as float32
    v64 = np.random.default_rng(0).random((8, 3))
    np.testing.assert_array_equal(proxima.Mesh(v64, f).vertices, v64.astype(np.float32))


def test_mesh_round_trip_polygons():
    v, f = quad_grid_arrays(n=2)
    m = proxima.Mesh(v, f)
    assert isinstance(m.faces, np.ndarray) and m.faces.shape == f.shape
    np.testing.assert_array_equal(m.faces, f)
    assert len(m) == len(f)
    mixed = [[0, 1, 2], [0, 2, 3, 4], [4, 5, 6, 7, 1]]
    vv = np.random.default_rng(1).random((8, 3))
    m = proxima.Mesh(vv, mixed)
    assert isinstance(m.faces, list) and len(m) == 3
    assert [f.tolist() for f in m.faces] == mixed
    assert all(f.dtype == np.int64 for f in m.faces)
    # a list of equal-length faces comes back as an array
    m = proxima.Mesh(vv, [np.array([0, 1, 2, 3]), np.array([4, 5, 6, 7])])
    assert isinstance(m.faces, np.ndarray) and m.faces.tolist() == [[0, 1, 2, 3], [4, 5, 6, 7]]


def test_used_vertices_are_those_the_faces_name():
    rng = np.random.default_rng(2)
    vv = rng.random((12, 3))
    for faces in ([[0, 1, 2], [0, 2, 3, 4], [4, 5, 6, 7, 1]], [[3, 9, 10], [10, 9, 2]], np.zeros((0, 3), np.int64)):
        try:
            m = proxima.Mesh(vv, faces)
        except ValueError:
            continue
        expected = np.zeros(len(vv), bool)
        for f in faces:
            expected[np.asarray(f, np.int64)] = True
        used = m.used_vertices
        assert used.dtype == np.bool_ and used.shape == (12,)
        np.testing.assert_array_equal(used, expected)


def test_empty_mesh_is_usable_or_refused():
    """A mesh of no faces either raises ValueError or answers with misses."""
    try:
        m = proxima.Mesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
    except ValueError:
        return
    try:
        _, d, i = m.closest_points([[0.0, 0.0, 0.0]])
    except ValueError:
        return
    assert np.isinf(d).all() and (i == -1).all()


def test_from_trimesh():
    trimesh = pytest.importorskip("trimesh")
    tm = trimesh.creation.icosphere(subdivisions=2)
    m = proxima.Mesh.from_trimesh(tm)
    np.testing.assert_array_equal(m.vertices, tm.vertices.astype(np.float32))
    np.testing.assert_array_equal(m.faces, tm.faces)
    pts = np.random.default_rng(0).normal(size=(50, 3))
    r = np.linalg.norm(pts, axis=1)
    clear = (r < 0.95) | (r > 1.0)  # the flat faces lie between radius ~0.96 and 1
    np.testing.assert_array_equal(m.contains(pts)[clear], (r < 0.95)[clear])
    box = trimesh.creation.box(extents=(1, 2, 3))
    mb = proxima.Mesh.from_trimesh(box)
    np.testing.assert_allclose(mb.bounds, box.bounds)
    np.testing.assert_allclose(mb.winding_number([[0, 0, 0], [5, 0, 0]]), [1, 0], atol=1e-3)


def test_from_trimesh_rejects_other_objects():
    for bad in (None, 3, "mesh", object()):
        try:
            proxima.Mesh.from_trimesh(bad)
        except BaseException as e:  # noqa: B036
            assert "Panic" not in type(e).__name__
            assert isinstance(e, (TypeError, ValueError, AttributeError)), repr(e)
        else:
            pytest.fail(f"from_trimesh({bad!r}) accepted")


@pytest.mark.parametrize("name", ["spot_triangulated.obj", "fandisk.obj", "stanford-bunny.obj"])
def test_load_glb_written_by_trimesh(name, tmp_path):
    """A shared mesh as a two-node GLB scene written by trimesh (the second
    instance moved and turned): proxima reads what trimesh reads back."""
    trimesh = pytest.importorskip("trimesh")
    source = data_path(name)
    loaded = trimesh_load(source)  # without materials (textures would need PIL)
    mesh = trimesh.Trimesh(loaded.vertices, loaded.faces, process=False)
    scene = trimesh.Scene()
    scene.add_geometry(mesh, node_name="a", geom_name="g")
    turn = trimesh.transformations.rotation_matrix(0.7, [0.3, 1.0, 0.2], [0.1, 0.0, 0.0])
    turn[:3, 3] += [2.0, -1.0, 0.5]
    scene.add_geometry(mesh, node_name="b", geom_name="g", transform=turn)
    path = tmp_path / "scene.glb"
    scene.export(path)
    ours = proxima.load(path)
    theirs = trimesh.load(path, process=False, force="mesh")
    assert ours.faces.shape == theirs.faces.shape == (2 * len(mesh.faces), 3)
    np.testing.assert_array_equal(ours.faces, theirs.faces)
    # The two instances, in whichever order each reader lists the nodes.
    n = len(mesh.vertices)
    a, b = ours.vertices[:n], ours.vertices[n:]
    c, d = np.asarray(theirs.vertices[:n]), np.asarray(theirs.vertices[n:])
    if np.abs(a - c).max() > np.abs(a - d).max():
        c, d = d, c
    np.testing.assert_allclose(a, c, rtol=0, atol=1e-5)
    np.testing.assert_allclose(b, d, rtol=0, atol=1e-5)
    np.testing.assert_allclose(a, np.asarray(mesh.vertices), rtol=0, atol=1e-6)
    # And the dataset pipeline takes it as any mesh file.
    from proxima.dataset import is_mesh_file, mesh_stem

    assert is_mesh_file(path) and mesh_stem(path) == "scene"

"""Helpers of test_dataset.py: small mesh files, a brute-force winding number,
npz comparison."""

import os
from pathlib import Path

import numpy as np

import proxima


def write_obj(path, vertices, faces):
    """An OBJ of float32 vertices (printed with 9 significant digits: they read
    back exactly) and faces of any sizes."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    v = np.asarray(vertices, dtype=np.float32)
    lines = ["# written by test_dataset.py"]
    lines += [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in v.tolist()]
    lines += ["f " + " ".join(str(int(i) + 1) for i in face) for face in faces]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_off(path, vertices, faces):
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    v = np.asarray(vertices, dtype=np.float32)
    lines = ["OFF", f"{len(v)} {len(faces)} 0"]
    lines += [f"{x:.9g} {y:.9g} {z:.9g}" for x, y, z in v.tolist()]
    lines += [f"{len(face)} " + " ".join(str(int(i)) for i in face) for face in faces]
    path.write_text("\n".join(lines) + "\n")
    return path


def open_icosphere(frequency=8, cut=0.6, seed=1):
    """A noisy icosphere without the faces whose centroid has z > cut: an open
    mesh (a cap removed)."""
    mesh = proxima.noisy_icosphere(frequency, seed=seed)
    v, f = mesh.vertices, np.asarray(mesh.faces)
    keep = v[f].mean(axis=1)[:, 2] <= cut
    return v, f[keep]


def winding_brute(points, vertices, triangles, block=256):
    """The exact generalized winding number (sum of solid angles, Van
    Oosterom & Strackee), float64, of every point over every triangle."""
    p = np.asarray(points, dtype=np.float64)
    tri = np.asarray(vertices, dtype=np.float64)[np.asarray(triangles)]
    out = np.empty(len(p))
    for s in range(0, len(p), block):
        q = p[s : s + block, None, None, :]
        d = tri[None] - q  # (b, F, 3, 3)
        a, b, c = d[..., 0, :], d[..., 1, :], d[..., 2, :]
        la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
        det = np.einsum("...i,...i", a, np.cross(b, c))
        den = la * lb * lc + np.einsum("...i,...i", a, b) * lc + np.einsum("...i,...i", b, c) * la + np.einsum("...i,...i", c, a) * lb
        out[s : s + block] = (2.0 * np.arctan2(det, den)).sum(axis=1) / (4.0 * np.pi)
    return out


def fan(faces):
    """Triangles (T, 3) of faces given as an array or a list of polygons."""
    tris = []
    for face in faces:
        face = list(face)
        tris += [[face[0], face[i], face[i + 1]] for i in range(1, len(face) - 1)]
    return np.array(tris, dtype=np.int64)


def npz_arrays(path):
    with np.load(path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def assert_same_npz(a, b):
    """The same keys, dtypes, shapes and bits."""
    x, y = npz_arrays(a), npz_arrays(b)
    assert sorted(x) == sorted(y), (a, b, sorted(x), sorted(y))
    for key in x:
        assert x[key].dtype == y[key].dtype, (a, key, x[key].dtype, y[key].dtype)
        assert x[key].shape == y[key].shape, (a, key)
        assert x[key].tobytes() == y[key].tobytes(), f"{a}: {key} differs"


def stats(directory):
    """name -> (inode, mtime_ns) of the npz outputs of a folder."""
    return {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in Path(directory).glob("*.npz")}


def tmp_files(directory):
    return sorted(p.name for p in Path(directory).iterdir() if ".npz.tmp-" in p.name)


def read_failures(directory):
    import json

    path = Path(directory) / "failures.jsonl"
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def env_without(*names):
    env = dict(os.environ)
    for name in names:
        env.pop(name, None)
    return env

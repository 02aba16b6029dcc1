"""proxima.dataset: sample_corpus on the local and Ray engines, outputs against
proxima's own single-point queries and a brute-force winding number, and
fault tolerance (corrupt meshes, a killed job resumed, a killed Ray actor).

The tests that start Ray carry ``@pytest.mark.ray`` (``-m ray`` / ``-m "not
ray"``) and skip with a note when Ray Data is not installed
(``pip install -r tests/requirements-ray.txt``)."""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import proxima
import proxima.dataset
from conftest import DATA, DATA_NOTE, REPO_ROOT, quad_grid_arrays
from dataset_helpers import (
    assert_same_npz,
    env_without,
    fan,
    npz_arrays,
    open_icosphere,
    read_failures,
    stats,
    tmp_files,
    winding_brute,
    write_obj,
    write_off,
)
from proxima.dataset import mesh_names, resolve_inputs, sample_corpus
from dataset_crash import CRASH_ENV, site_dir
from proxima.dataset.sampling import is_complete, Options

POINTS = 20_000
GRID = 12
SHARED = ["bunny-npm.obj", "spot_quadrangulated.obj", "teapot.obj", "blade.off"]
GOOD = ["ico", "open_ico", "quads", "ico_off"]  # + two "ico" in sub folders (a stem collision)
CORRUPT = {"bad.ply": "ValueError", "empty.obj": "ValueError", "nofaces.obj": "ValueError", "missing.obj": "FileNotFoundError"}


def make_corpus(root):
    """Generated meshes (closed, open, quads, OFF, a stem collision) plus the
    shared ones when present; returns the list file naming them all."""
    root = Path(root)
    ico = proxima.noisy_icosphere(8)
    write_obj(root / "gen" / "ico.obj", ico.vertices, ico.faces)
    write_obj(root / "gen" / "open_ico.obj", *open_icosphere(8))
    write_obj(root / "gen" / "quads.obj", *quad_grid_arrays(5))
    other = proxima.noisy_icosphere(6, seed=2)
    write_off(root / "gen" / "ico_off.off", other.vertices, other.faces)
    write_obj(root / "gen" / "a" / "twin.obj", ico.vertices, ico.faces)
    write_obj(root / "gen" / "b" / "twin.obj", other.vertices, other.faces)
    paths = sorted(str(p) for p in (root / "gen").rglob("*.o*"))
    if DATA is not None:
        paths += [str(DATA / n) for n in SHARED if (DATA / n).exists()]
    listing = root / "corpus.txt"
    listing.write_text("# the test corpus\n" + "\n".join(paths) + "\n")
    return listing


def add_corrupt(root):
    root = Path(root) / "corrupt"
    root.mkdir(parents=True, exist_ok=True)
    (root / "bad.ply").write_text("ply\nformat nonsense 9.9\nend_header\n")
    (root / "empty.obj").write_text("# nothing\n")
    (root / "nofaces.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n")
    return [str(root / n) for n in CORRUPT]


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    if DATA is None:
        print("NOTE: " + DATA_NOTE)
    return make_corpus(tmp_path_factory.mktemp("corpus"))


@pytest.fixture(scope="module")
def local_out(corpus, tmp_path_factory):
    """The corpus sampled once by the local engine (occupancy and a grid)."""
    out = tmp_path_factory.mktemp("local")
    summary = sample_corpus(corpus, out, n_points=POINTS, grid=GRID, kind="occupancy", seed=7, engine="local", workers=1, threads=2)
    assert summary["failed"] == 0, read_failures(out)
    return out, summary


def expected_names(corpus):
    return mesh_names(resolve_inputs(corpus))


# --- inputs and names ------------------------------------------------------------------


def test_inputs_and_names(tmp_path):
    for rel in ["x/bunny.obj", "y/bunny.obj", "y/z/bunny.PLY.gz", "cow.off", "notes.md"]:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_text("")
    found = resolve_inputs(tmp_path)
    assert [p.name for p in found] == ["cow.off", "bunny.obj", "bunny.obj", "bunny.PLY.gz"]
    names = mesh_names(found)
    assert names[0] == "cow" and len(set(names)) == 4
    assert all(n.startswith("bunny-") and len(n) == len("bunny-") + 8 for n in names[1:])
    # The same names for the same files wherever the corpus lies, in any order.
    moved = tmp_path.parent / (tmp_path.name + "-moved")
    shutil.copytree(tmp_path, moved)
    assert mesh_names(resolve_inputs([moved / "y", moved / "x", moved / "cow.off"])) == names
    assert [p.name for p in resolve_inputs(str(tmp_path / "**" / "*.obj"))] == ["bunny.obj", "bunny.obj"]
    listing = tmp_path / "list.txt"
    listing.write_text("cow.off\n# comment\n\nx/bunny.obj\ncow.off\n")
    assert [p.name for p in resolve_inputs(listing)] == ["cow.off", "bunny.obj"]
    with pytest.raises(FileNotFoundError):
        resolve_inputs(tmp_path / "nowhere")


# --- outputs ---------------------------------------------------------------------------


def test_layout_and_normalization(corpus, local_out):
    out, summary = local_out
    names = expected_names(corpus)
    assert summary["done"] == len(names) and summary["samples"] == len(names) * (POINTS + GRID**3)
    assert sorted(p.stem for p in out.glob("*.npz")) == sorted(names)
    assert not (out / "failures.jsonl").exists() and tmp_files(out) == []
    for name in names:
        z = npz_arrays(out / f"{name}.npz")
        assert z["points"].dtype == np.float32 and z["points"].shape == (POINTS, 3)
        assert z["sdf"].dtype == np.float32 and z["sdf"].shape == (POINTS,)
        assert z["occupancy"].dtype == np.bool_ and np.array_equal(z["occupancy"], z["sdf"] < 0)
        assert z["grid"].dtype == np.float32 and z["grid"].shape == (GRID,) * 3
        meta = json.loads(str(z["meta"]))
        assert meta["name"] == name and meta["options"]["normalize"] == "unit-cube"
        n_near = int(z["n_near"])
        assert n_near == POINTS - round(0.1 * POINTS)
        volume = float(z["volume"])
        assert volume == 0.55 and np.abs(z["points"][n_near:]).max() <= volume
        # unit cube: the normalized used vertices span a longest side of 1, centred.
        source = proxima.load(meta["source"])
        used = np.unique(fan(source.faces))
        v = (source.vertices[used].astype(np.float64) - z["offset"]) / z["scale"]
        lo, hi = v.min(0), v.max(0)
        assert abs((hi - lo).max() - 1.0) < 1e-12 and np.abs(lo + hi).max() < 1e-12
        # Some points inside and some outside (every mesh here encloses volume or nearly).
        assert 0 < z["occupancy"].sum() < POINTS, name


def test_unit_sphere_and_near_sigma(corpus, tmp_path):
    out = tmp_path / "sphere"
    paths = [p for p in resolve_inputs(corpus) if p.stem in ("ico", "quads")]
    sample_corpus(paths, out, n_points=POINTS, near_sigma=0.02, engine="local", seed=3)
    for path in paths:
        z = npz_arrays(out / f"{path.stem}.npz")
        source = proxima.load(path)
        v = (source.vertices.astype(np.float64) - z["offset"]) / z["scale"]
        assert abs(np.linalg.norm(v, axis=1).max() - 1 / 1.03) < 1e-12  # DeepSDF's padding
        assert float(z["volume"]) == 1.0 and np.abs(z["points"]).max() <= 1.0
        # The offsets' per-axis sigma is near_sigma in normalized units: the
        # normal component's |.| has mean sigma * sqrt(2 / pi) (flat-surface limit).
        near = np.abs(z["sdf"][: int(z["n_near"])]).mean()
        assert abs(near / (0.02 * np.sqrt(2 / np.pi)) - 1) < 0.1, near


def rebuilt(z):
    """The normalized mesh, rebuilt from the source and the saved transform
    (normalized = (original - offset) / scale, rounded to float32)."""
    meta = json.loads(str(z["meta"]))
    source = proxima.load(meta["source"])
    v = ((source.vertices.astype(np.float64) - z["offset"]) / float(z["scale"])).astype(np.float32)
    return proxima.Mesh(v, source.faces)


def test_occupancy_networks_loader_reads_outputs(corpus, local_out):
    """What im2mesh's PointsField (unpackbits, with_transforms) does with a
    points.npz, done on our files: the same occupancies and transform."""
    out, _ = local_out
    for name in expected_names(corpus):
        points_dict = np.load(out / f"{name}.npz")
        points = points_dict["points"]
        occupancies = np.unpackbits(points_dict["occupancies"])[: points.shape[0]].astype(np.float32)
        np.testing.assert_array_equal(occupancies, points_dict["occupancy"].astype(np.float32))
        np.testing.assert_array_equal(occupancies == 1, points_dict["sdf"] < 0)
        loc, scale = points_dict["loc"], points_dict["scale"]
        assert loc.shape == (3,) and scale.shape == ()
        np.testing.assert_array_equal(loc, points_dict["offset"])


def test_deepsdf_loader_reads_outputs(corpus, tmp_path):
    """What DeepSDF's data.py does with an SdfSamples npz (read pos and neg,
    take half of the samples from each), done on our files."""
    paths = [p for p in resolve_inputs(corpus) if p.stem in ("ico", "open_ico")]
    summary = sample_corpus(paths, tmp_path, n_points=4000, seed=3, engine="local", deepsdf=True)
    assert summary["done"] == 2
    plain = sample_corpus(paths, tmp_path / "plain", n_points=4000, seed=3, engine="local")
    assert plain["done"] == 2
    for name in ("ico", "open_ico"):
        z = np.load(tmp_path / f"{name}.npz")
        pos, neg = z["pos"], z["neg"]
        assert pos.dtype == neg.dtype == np.float32 and pos.shape[1] == neg.shape[1] == 4
        assert len(pos) + len(neg) == 4000 and len(pos) > 0 and len(neg) > 0
        assert np.all(pos[:, 3] >= 0) and np.all(neg[:, 3] < 0)
        rows = np.concatenate([z["points"], z["sdf"][:, None]], axis=1)
        np.testing.assert_array_equal(pos, rows[z["sdf"] >= 0])
        np.testing.assert_array_equal(neg, rows[z["sdf"] < 0])
        # DeepSDF's unpack_sdf_samples: a random half from each of pos and neg.
        rng = np.random.default_rng(0)
        half = 500
        samples = np.concatenate([pos[rng.integers(0, len(pos), half)], neg[rng.integers(0, len(neg), half)]])
        assert samples.shape == (1000, 4)
        assert np.all(samples[:half, 3] >= 0) and np.all(samples[half:, 3] < 0)
        # The option adds keys only: the other arrays equal a run without it.
        other = np.load(tmp_path / "plain" / f"{name}.npz")
        for key in ("points", "sdf", "scale", "offset"):
            np.testing.assert_array_equal(z[key], other[key])
        assert "pos" not in other.files


def test_sdf_equals_single_point_queries(corpus, local_out):
    out, _ = local_out
    rng = np.random.default_rng(0)
    for name in expected_names(corpus):
        z = npz_arrays(out / f"{name}.npz")
        mesh = rebuilt(z)
        pick = rng.choice(POINTS, 1000, replace=False)
        single = np.array([mesh.signed_distance(z["points"][i][None], threads=1)[0] for i in pick], dtype=np.float32)
        assert np.array_equal(single, z["sdf"][pick]), name
        # The grid: cell (i, j, k) at (x_i, x_j, x_k), x_i = -v + cell * (i + 0.5)
        # in float32, v = float32(volume), cell = 2 v / N (format 2).
        half = np.float32(z["volume"])
        cell = (half - -half) / np.float32(GRID)
        centres = -half + cell * (np.arange(GRID, dtype=np.float32) + np.float32(0.5))
        ijk = rng.integers(0, GRID, (50, 3))
        at = centres[ijk]
        assert at.dtype == np.float32
        assert np.array_equal(mesh.signed_distance(at).astype(np.float32), z["grid"][ijk[:, 0], ijk[:, 1], ijk[:, 2]]), name


@pytest.mark.parametrize("which", ["closed", "open"])
def test_sign_equals_brute_force_winding(tmp_path, which):
    ico = proxima.noisy_icosphere(6)
    v, f = (ico.vertices, ico.faces) if which == "closed" else open_icosphere(6)
    path = write_obj(tmp_path / f"{which}.obj", v, f)
    sample_corpus(path, tmp_path / "out", n_points=4000, near_sigma=0.05, uniform_fraction=0.5, engine="local")
    z = npz_arrays(tmp_path / "out" / f"{which}.npz")
    mesh = rebuilt(z)
    pick = np.random.default_rng(1).choice(4000, 1000, replace=False)
    w = winding_brute(z["points"][pick], mesh.vertices, mesh.faces)
    inside = z["sdf"][pick] < 0
    # proxima's far-field expansion is within ~0.03 of the exact sum: exclude
    # the points whose exact winding number is that close to 1/2.
    clear = np.abs(w - 0.5) > 0.05
    assert clear.sum() >= 950, (which, clear.sum())
    assert np.array_equal(inside[clear], w[clear] > 0.5), (which, np.flatnonzero(inside[clear] != (w[clear] > 0.5)))
    if which == "open":
        assert ((w > 0.05) & (w < 0.95)).sum() > 10  # fractional winding numbers near the hole were tested


def test_seed_depends_on_name_not_order(corpus, tmp_path):
    paths = [p for p in resolve_inputs(corpus) if p.stem in ("ico", "ico_off")]
    sample_corpus(paths, tmp_path / "a", n_points=1000, engine="local")
    sample_corpus(paths[::-1], tmp_path / "b", n_points=1000, engine="local", workers=2)
    for p in paths:
        assert_same_npz(tmp_path / "a" / f"{p.stem}.npz", tmp_path / "b" / f"{p.stem}.npz")
    renamed = tmp_path / "renamed.obj"
    shutil.copy(paths[0], renamed)
    sample_corpus(renamed, tmp_path / "c", n_points=1000, engine="local")
    a, c = npz_arrays(tmp_path / "a" / f"{paths[0].stem}.npz"), npz_arrays(tmp_path / "c" / "renamed.npz")
    assert a["scale"] == c["scale"] and not np.array_equal(a["points"], c["points"])


def test_process_pool_matches_thread_pool(corpus, local_out, tmp_path):
    out, _ = local_out
    summary = sample_corpus(corpus, tmp_path, n_points=POINTS, grid=GRID, kind="occupancy", seed=7, engine="local", local_pool="process", workers=2)
    assert summary["done"] == summary["meshes"]
    for name in expected_names(corpus):
        assert_same_npz(out / f"{name}.npz", tmp_path / f"{name}.npz")


def test_options_change_recomputes(corpus, tmp_path):
    path = [p for p in resolve_inputs(corpus) if p.stem == "ico"]
    first = sample_corpus(path, tmp_path, n_points=1000, engine="local")
    again = sample_corpus(path, tmp_path, n_points=1000, engine="local")
    assert (first["done"], again["skipped"], again["done"]) == (1, 1, 0)
    changed = sample_corpus(path, tmp_path, n_points=500, engine="local")
    assert changed["done"] == 1 and npz_arrays(tmp_path / "ico.npz")["points"].shape == (500, 3)


# --- bad options -----------------------------------------------------------------------

BAD_OPTIONS = [
    ({"n_points": -1}, "n_points"),
    ({"n_points": 0}, "nothing to sample"),
    ({"near_sigma": float("nan")}, "near_sigma"),
    ({"uniform_fraction": 1.5}, "uniform_fraction"),
    ({"grid": 0}, "grid"),
    ({"grid": 2000}, "grid"),
    ({"kind": "density"}, "kind"),
    ({"seed": -1}, "seed"),
    ({"normalize": "unit-ball"}, "normalize"),
    ({"padding": -0.5}, "padding"),
    ({"engine": "dask"}, "engine"),
    ({"threads": 0}, "threads"),
    ({"threads": 10**6}, "threads"),
    ({"workers": 0}, "workers"),
    ({"workers": 10**6}, "workers"),  # local: one thread each
    ({"local_pool": "fiber"}, "local_pool"),
    ({"deepsdf": "yes"}, "deepsdf"),
    ({"n_points": 10**10}, "n_points 10000000000 per mesh"),  # 1.8 TiB at any default budget
]


@pytest.mark.parametrize("options,message", BAD_OPTIONS, ids=[m.split(":")[0] + "-" + str(o) for o, m in BAD_OPTIONS])
def test_bad_options_are_refused_before_any_work(corpus, tmp_path, options, message):
    out = tmp_path / "out"
    kwargs = {"engine": "local", **options}
    with pytest.raises(ValueError, match=re.escape(message)):
        sample_corpus(corpus, out, **kwargs)
    assert not out.exists()  # refused before the output folder, or any mesh, was touched


def test_sizes_are_checked_against_the_memory_budget(corpus, tmp_path, monkeypatch):
    monkeypatch.setenv("PROXIMA_MEMORY_BUDGET", "512M")
    assert proxima.memory_budget() == 512 << 20
    out = tmp_path / "out"
    # A grid of 256^3 cells is 128 MiB (the values and their C-order copy): it
    # fits; 512^3 is 1 GiB.
    with pytest.raises(ValueError, match=r"^grid 512 per mesh.*: needs about .* more than the memory budget of 512.0 MiB"):
        sample_corpus(corpus, out, n_points=1000, grid=512, engine="local")
    # 2M points fit one mesh (about 381 MiB), not two side by side in one
    # process; the process pool (one mesh per process) and Ray's actors hold
    # one each.
    with pytest.raises(ValueError, match=r"^n_points 2000000 per mesh x 2 meshes at a time in one process \(workers\): needs about"):
        sample_corpus(corpus, out, n_points=2_000_000, engine="local", workers=2)
    assert not out.exists()
    from proxima.dataset import check_memory

    check_memory(Options(n_points=2_000_000), 1)
    check_memory(Options(n_points=1000, grid=256), 1)
    monkeypatch.setenv("PROXIMA_MEMORY_BUDGET", "lots")
    with pytest.raises(ValueError, match="PROXIMA_MEMORY_BUDGET"):
        proxima.memory_budget()
    with pytest.raises(ValueError, match="PROXIMA_MEMORY_BUDGET"):
        sample_corpus(corpus, out, n_points=1000, engine="local")


def test_command_refuses_bad_options_in_one_line(corpus, tmp_path):
    result = subprocess.run(
        [sys.executable, "-m", "proxima.dataset", str(corpus), str(tmp_path / "out"), "--points", str(10**10), "--engine", "local"],
        capture_output=True, text=True, timeout=120,
    )
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: n_points 10000000000 per mesh"), result.stderr
    assert result.stdout == "" and not (tmp_path / "out").exists()


# --- fault tolerance -------------------------------------------------------------------


def test_corrupt_meshes_are_recorded(corpus, tmp_path):
    bad = add_corrupt(tmp_path)  # missing.obj is never created
    good = [str(p) for p in resolve_inputs(corpus) if p.stem in ("ico", "quads")]
    summary = sample_corpus(good + bad, tmp_path / "out", n_points=1000, engine="local", workers=2)
    assert (summary["done"], summary["failed"]) == (2, 4)
    failures = read_failures(tmp_path / "out")
    assert sorted(Path(f["path"]).name for f in failures) == sorted(CORRUPT)
    for f in failures:
        assert f["type"] == CORRUPT[Path(f["path"]).name] and f["error"], f
        assert set(f) >= {"path", "error", "type"}
    assert sorted(p.stem for p in (tmp_path / "out").glob("*.npz")) == ["ico", "quads"]
    # The command exits with 1 and says so; a rerun skips the good ones.
    result = subprocess.run(
        [sys.executable, "-m", "proxima.dataset", *good, *bad, str(tmp_path / "out"), "--points", "1000", "--engine", "local"],
        capture_output=True, text=True, timeout=120,
    )
    assert result.returncode == 1, result.stderr
    assert json.loads(result.stdout[: result.stdout.index("\n}") + 2])["skipped"] == 2


def test_killed_job_resumes(tmp_path):
    src = tmp_path / "meshes"
    for i in range(24):
        mesh = proxima.noisy_icosphere(24, seed=i + 1)
        write_obj(src / f"m{i:02d}.obj", mesh.vertices, mesh.faces)
    out = tmp_path / "out"
    command = [sys.executable, "-m", "proxima.dataset", str(src), str(out), "--engine", "local", "--workers", "1", "--threads", "1", "--points", "150000"]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env_without(CRASH_ENV))
    deadline = time.monotonic() + 60
    while len(list(out.glob("*.npz"))) < 3 and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    process.send_signal(signal.SIGKILL)
    process.wait()
    before = stats(out)
    assert 3 <= len(before) < 24, f"the job was not stopped half way: {len(before)} outputs"
    result = subprocess.run(command, capture_output=True, text=True, timeout=300, env=env_without(CRASH_ENV))
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout[: result.stdout.index("\n}") + 2])
    assert summary["skipped"] == len(before) and summary["done"] == 24 - len(before), summary
    after = stats(out)
    assert len(after) == 24 and tmp_files(out) == [] and read_failures(out) == []
    assert {k: after[k] for k in before} == before  # the finished ones were not rewritten
    options = Options(n_points=150_000)
    assert all(is_complete(out / name, options) for name in after)


def test_library_samples_and_grid_are_the_documented_ones():
    """Mesh.training_samples and Mesh.sdf_grid, which the dataset writes: the
    split, the boxes, the distances (against Mesh.signed_distance at the same
    points) and the same arrays on any thread count."""
    mesh = proxima.noisy_icosphere(8)
    points, sdf = mesh.training_samples(3001, 0.01, uniform_fraction=0.25, cube=1.5, seed=3, threads=1)
    near, uniform = proxima.training_sample_counts(3001, 0.25)
    assert (near, uniform) == (2251, 750)
    assert points.shape == (3001, 3) and points.dtype == np.float32 and sdf.dtype == np.float32
    again = mesh.training_samples(3001, 0.01, uniform_fraction=0.25, cube=1.5, seed=3, threads=3)
    np.testing.assert_array_equal(points, again[0])
    np.testing.assert_array_equal(sdf, again[1])
    np.testing.assert_array_equal(sdf, mesh.signed_distance(points).astype(np.float32))
    assert np.abs(sdf[:near]).max() < 0.01 * 9  # a gaussian of 53-bit uniforms stays within 8.6 sigma
    assert np.abs(points[near:]).max() <= 1.5 and np.abs(points[near:]).max() > 1.4
    assert not np.array_equal(points, mesh.training_samples(3001, 0.01, 0.25, cube=1.5, seed=4)[0])
    # Without a cube: the bounding box grown by 5% per side.
    lo, hi = mesh.bounds
    box = mesh.training_samples(100, 0.01, uniform_fraction=1.0, seed=3)[0]
    assert np.all(box >= lo - 0.05 * (hi - lo) - 1e-6) and np.all(box <= hi + 0.05 * (hi - lo) + 1e-6)

    n, half = 6, np.float32(1.25)
    grid = mesh.sdf_grid(n, cube=1.25, threads=2)
    assert grid.shape == (n, n, n) and grid.dtype == np.float32 and grid.flags["C_CONTIGUOUS"]
    cell = (half - (-half)) / np.float32(n)
    x = -half + cell * (np.arange(n, dtype=np.float32) + np.float32(0.5))
    centres = np.stack(np.meshgrid(x, x, x, indexing="ij"), axis=-1).reshape(-1, 3)
    np.testing.assert_array_equal(grid.ravel(), mesh.signed_distance(centres).astype(np.float32))
    np.testing.assert_array_equal(grid, mesh.sdf_grid(n, cube=1.25, threads=1))


def test_mesh_suffixes_are_the_library_formats():
    from proxima.dataset.sampling import MESH_SUFFIXES, is_mesh_file, mesh_stem

    assert MESH_SUFFIXES == (".obj", ".ply", ".stl", ".off", ".glb") == tuple(proxima.mesh_suffixes())
    for suffix in MESH_SUFFIXES:
        assert is_mesh_file(f"m{suffix}") and is_mesh_file(f"m{suffix.upper()}.gz") and mesh_stem(f"x/m{suffix}.gz") == "m"
    assert not is_mesh_file("m.npz")


def proxima_cli():
    """The command line of this checkout: ``PROXIMA_CLI`` (scripts/test sets
    it to the binary ``cargo test`` built), or ``proxima`` as ``cargo build``
    makes it (the dev profile: every dependency compiled again on a clean
    checkout)."""
    if os.environ.get("PROXIMA_CLI"):
        return os.environ["PROXIMA_CLI"]
    cargo = shutil.which("cargo")
    if cargo is None:
        pytest.skip("no cargo to build the proxima command line: set PROXIMA_CLI to it")
    result = subprocess.run(
        [cargo, "build", "-q", "-p", "proxima-cli", "--bin", "proxima", "--message-format", "json"],
        cwd=REPO_ROOT, capture_output=True, text=True, timeout=3600, check=True,
    )
    for line in result.stdout.splitlines():
        message = json.loads(line)
        if message.get("reason") == "compiler-artifact" and message.get("executable"):
            return message["executable"]
    pytest.fail(f"cargo built no proxima executable: {result.stderr}")


def test_command_line_samples_are_the_dataset_samples(corpus, tmp_path):
    """One recipe: ``proxima sdf --sample`` (and ``--grid``) on the normalized
    mesh, with the dataset's options and the mesh's ``sample_seed``, writes the
    dataset's points, signed distances and grid, bit for bit."""
    cli = proxima_cli()
    path = next(p for p in resolve_inputs(corpus) if p.name == "open_ico.obj")
    out = tmp_path / "out"
    n, sigma, fraction, grid = 3001, 0.02, 0.3, 9
    summary = sample_corpus([path], out, n_points=n, near_sigma=sigma, uniform_fraction=fraction, grid=grid, seed=5, engine="local")
    assert summary["done"] == 1, summary
    with np.load(out / "open_ico.npz") as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(str(arrays["meta"]))
    assert meta["format"] == 2 and meta["sample_seed"] == proxima.dataset.sample_seed(5, "open_ico")
    source = proxima.load(path)
    normalized = proxima.dataset.normalize_vertices(source.vertices, float(arrays["scale"]), arrays["offset"])
    mesh_file = write_obj(tmp_path / "normalized.obj", normalized, source.faces)
    volume = float(arrays["volume"])
    common = [cli, "sdf", str(mesh_file), "--cube", repr(volume)]
    samples, values = tmp_path / "s.npz", tmp_path / "g.npy"
    for extra in (
        ["--sample", str(n), "--near-sigma", repr(sigma), "--uniform-fraction", repr(fraction), "--seed", str(meta["sample_seed"]), "--out", str(samples)],
        ["--grid", str(grid), "--out", str(values)],
    ):
        result = subprocess.run(common + extra, capture_output=True, text=True, timeout=300)
        assert result.returncode == 0, result.stderr
    with np.load(samples) as cli_samples:
        np.testing.assert_array_equal(cli_samples["points"], arrays["points"])
        np.testing.assert_array_equal(cli_samples["sdf"], arrays["sdf"])
    assert int(arrays["n_near"]) == proxima.training_sample_counts(n, fraction)[0] == n - round(n * fraction)
    np.testing.assert_array_equal(np.load(values), arrays["grid"])


# --- Ray -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def ray_local(tmp_path_factory):
    try:
        import ray
        import ray.data  # noqa: F401
    except ImportError as error:
        pytest.skip(f"Ray Data is not installed ({error}); pip install -r tests/requirements-ray.txt")
    if ray.is_initialized():
        ray.shutdown()
    # The actors' processes start from the instance's: with the crash hook's
    # folder on their path, those given CRASH_ENV install it (dataset_crash).
    old_path = os.environ.get("PYTHONPATH")
    hook = site_dir(tmp_path_factory.mktemp("crash_hook"))
    os.environ["PYTHONPATH"] = os.pathsep.join([str(hook)] + ([old_path] if old_path else []))
    try:
        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
        yield ray
    finally:
        ray.shutdown()
        if old_path is None:
            os.environ.pop("PYTHONPATH", None)
        else:
            os.environ["PYTHONPATH"] = old_path


@pytest.mark.ray
def test_ray_equals_local(ray_local, corpus, local_out, tmp_path):
    out, _ = local_out
    summary = sample_corpus(corpus, tmp_path, n_points=POINTS, grid=GRID, kind="occupancy", seed=7, workers=2, threads=1, progress=False)
    names = expected_names(corpus)
    assert summary["engine"] == "ray" and summary["done"] == len(names) and summary["failed"] == 0
    for name in names:
        assert_same_npz(out / f"{name}.npz", tmp_path / f"{name}.npz")
    before = stats(tmp_path)
    again = sample_corpus(corpus, tmp_path, n_points=POINTS, grid=GRID, kind="occupancy", seed=7, progress=False)
    assert again["skipped"] == len(names) and again["done"] == 0 and stats(tmp_path) == before
    assert ray_local.is_initialized()  # the caller's instance is left running


@pytest.mark.ray
def test_ray_corrupt_meshes(ray_local, corpus, tmp_path):
    bad = add_corrupt(tmp_path)[:3]
    good = [str(p) for p in resolve_inputs(corpus) if p.stem in ("ico", "open_ico")]
    summary = sample_corpus(good + bad, tmp_path / "out", n_points=1000, progress=False)
    assert (summary["done"], summary["failed"]) == (2, 3)
    assert sorted(Path(f["path"]).name for f in read_failures(tmp_path / "out")) == sorted(bad_name for bad_name in list(CORRUPT)[:3])


@pytest.mark.ray
def test_ray_actor_killed(ray_local, corpus, local_out, tmp_path, monkeypatch):
    out, _ = local_out
    names = expected_names(corpus)
    victim = "open_ico"
    marker = tmp_path / "crashed"
    # The actor writing open_ico's output exits abruptly after writing its
    # temporary file, the first time: Ray restarts it and retries the mesh.
    monkeypatch.setenv(CRASH_ENV, f"{victim}={marker}")
    result = tmp_path / "out"
    summary = sample_corpus(corpus, result, n_points=POINTS, grid=GRID, kind="occupancy", seed=7, workers=2, threads=1, progress=False)
    assert marker.exists(), "the fault was not injected"
    assert summary["done"] == len(names) and summary["failed"] == 0, summary
    assert sorted(p.stem for p in result.glob("*.npz")) == sorted(names)
    assert tmp_files(result) == [] and read_failures(result) == []
    assert sum(m["name"] == victim for m in summary["per_mesh"]) == 1
    for name in names:
        assert_same_npz(out / f"{name}.npz", result / f"{name}.npz")


@pytest.mark.ray
def test_ray_mesh_that_always_kills_its_actor(ray_local, corpus, tmp_path, monkeypatch):
    names = [p for p in resolve_inputs(corpus) if p.stem in ("ico", "open_ico", "quads")]
    monkeypatch.setenv(CRASH_ENV, "quads")  # every attempt at quads kills its actor
    summary = sample_corpus(names, tmp_path, n_points=1000, workers=2, max_task_retries=1, progress=False)
    assert (summary["done"], summary["failed"]) == (2, 1), summary
    failures = read_failures(tmp_path)
    assert [(f["name"], f["type"]) for f in failures] == [("quads", "WorkerDied")], failures
    assert "died on this mesh 2 times" in failures[0]["error"]
    assert sorted(p.stem for p in tmp_path.glob("*.npz")) == ["ico", "open_ico"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["failures.jsonl", "ico.npz", "open_ico.npz"]

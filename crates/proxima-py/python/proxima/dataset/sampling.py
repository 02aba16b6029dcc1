"""One mesh of a corpus: load, normalize, sample, write ``NAME.npz`` atomically.

Everything a mesh's output holds depends only on the mesh file's bytes, the
sampling options and the mesh's name (through :func:`mesh_seed`), never on
the engine, the worker, the thread count or the order of the corpus: the local
and Ray engines write the same arrays, bit for bit.

The points, their signed distances and the grid come from the library, the
recipe of ``proxima sdf --sample`` and ``--grid`` (``Mesh.training_samples``,
``Mesh.sdf_grid``): ``proxima sdf NORMALIZED_MESH --sample n_points
--near-sigma near_sigma --uniform-fraction uniform_fraction --cube volume
--seed SEED``, ``SEED`` the mesh's ``sample_seed`` in ``meta``, writes the same
``points`` and ``sdf``.

The npz layout (``np.load(path)``):

``points``    float32 (n, 3), normalized coordinates. The first ``n_near`` rows
              are near the surface (a point uniform on the faces by area plus
              a gaussian offset per axis of standard deviation ``near_sigma``,
              an absolute length in normalized units), the rest uniform in the
              cube ``[-volume, volume]^3`` (``volume`` rounded to float32).
``sdf``       float32 (n,), the signed distance to the normalized mesh,
              negative inside; inside is where the generalized winding number
              exceeds 1/2 (right on open and self-intersecting meshes).
``occupancy`` bool (n,), only for ``kind="occupancy"``: ``sdf < 0`` (a point
              exactly on the surface counts outside).
``occupancies`` uint8 (ceil(n / 8),) and
``loc``       float64 (3,), only for ``kind="occupancy"``: the same occupancy
              as ``np.packbits`` stores it, and ``offset`` again, under the
              names Occupancy Networks' ``points.npz`` uses (its loader,
              ``PointsField`` with ``unpackbits``, reads ``points``,
              ``occupancies``, ``loc`` and ``scale`` from this file as is).
``pos``, ``neg`` float32 (m, 4) and (n - m, 4), only with ``deepsdf=True``:
              the rows ``(x, y, z, sdf)`` with ``sdf >= 0`` and ``sdf < 0``, in
              the order of ``points``, as DeepSDF's ``SdfSamples`` files hold
              them (its loader reads this file as is).
``grid``      float32 (N, N, N), only with ``grid=N``: the signed distance at
              the centres of the cells of the cube ``[-volume, volume]^3`` cut
              in N^3 cells; ``grid[i, j, k]`` is at
              ``(x_i, x_j, x_k)``, ``x_i = -v + cell * (i + 0.5)`` in float32
              arithmetic, ``v = float32(volume)``, ``cell = (2 v) / N``
              (x first: C order, ``indexing="ij"``; ``proxima sdf --grid N
              --cube volume``'s values).
``scale``     float64 scalar and
``offset``    float64 (3,): the normalization,
              ``original = normalized * scale + offset``
              (so ``normalized = (original - offset) / scale``).
``volume``    float64 scalar, the half side of the sampling cube.
``n_near``    int64 scalar, the number of near-surface rows of ``points``.
``meta``      str (0-d), JSON: format version, name, source path, options,
              normalization, ``sample_seed`` (the library's seed of this
              mesh's samples) and the convention above.

Normalization (vertices that no face uses are ignored):

* ``"unit-sphere"`` (DeepSDF): the bounding box's centre goes to the origin and
  the vertex farthest from it to distance ``1 / (1 + padding)``; default
  padding 0.03 (DeepSDF's 1/1.03); ``volume`` 1 (DeepSDF samples in [-1, 1]^3).
* ``"unit-cube"`` (Occupancy Networks): the bounding box's centre goes to the
  origin and its longest side to ``1 / (1 + padding)``; default padding 0;
  ``volume`` 0.55 (Occupancy Networks' points padding 0.1: [-0.55, 0.55]^3).
"""

from __future__ import annotations

import json
import os
import secrets
import time
import zlib
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Dict, Optional

import numpy as np

import proxima

#: 2: the samples and the grid from the library's recipe (``proxima sdf
#: --sample``/``--grid``'s), with one seed per mesh (``sample_seed``); 1 drew
#: the uniform points and grid centres with numpy.
FORMAT_VERSION = 2

#: Mesh file suffixes (each also with ``.gz``): the formats ``proxima.load`` reads.
MESH_SUFFIXES = tuple(proxima.mesh_suffixes())

#: The temporary name of an output being written: ``NAME.npz.tmp-<hex>``.
TMP_MARKER = ".npz.tmp-"

NORMALIZATIONS = {
    # name: (default padding, half side of the sampling cube)
    "unit-sphere": (0.03, 1.0),
    "unit-cube": (0.0, 0.55),
}

KINDS = ("sdf", "occupancy")

#: Peak bytes of one mesh's processing per sample (the points, their sdf
#: and the query's per-point state and temporaries): at most 188 measured
#: (VmHWM, 250k to 2M points), rounded up. The mesh's own part (its
#: triangles, tree and winding-number expansions) is checked by the loader.
BYTES_PER_SAMPLE = 200

#: Bytes per grid cell: the library's values (x fastest) and their C-order copy.
BYTES_PER_GRID_CELL = 8

#: The count of a mesh's attempts in a Ray run: ``NAME.npz.attempts``.
ATTEMPTS_SUFFIX = ".npz.attempts"


@dataclass(frozen=True)
class Options:
    """What a mesh's output depends on (besides its file and name)."""

    n_points: int = 250_000
    near_sigma: float = 0.01
    uniform_fraction: float = 0.1
    grid: Optional[int] = None
    kind: str = "sdf"
    seed: int = 0
    normalize: str = "unit-sphere"
    padding: Optional[float] = None
    compress: bool = False
    deepsdf: bool = False

    def __post_init__(self):
        def check(ok, message):
            if not ok:
                raise ValueError(message)

        check(isinstance(self.n_points, (int, np.integer)) and self.n_points >= 0, f"n_points: {self.n_points!r} is not an integer >= 0")
        check(np.isfinite(self.near_sigma) and self.near_sigma >= 0, f"near_sigma: {self.near_sigma!r} is not a finite number >= 0")
        check(0.0 <= self.uniform_fraction <= 1.0, f"uniform_fraction: {self.uniform_fraction!r} is not in [0, 1]")
        check(
            self.grid is None or (isinstance(self.grid, (int, np.integer)) and 1 <= self.grid <= 1024),
            f"grid: {self.grid!r} is not None or an integer in [1, 1024]",
        )
        check(self.kind in KINDS, f"kind: {self.kind!r} is not one of {KINDS}")
        check(isinstance(self.seed, (int, np.integer)) and 0 <= self.seed < 2**63, f"seed: {self.seed!r} is not an integer in [0, 2**63)")
        check(self.normalize in NORMALIZATIONS, f"normalize: {self.normalize!r} is not one of {tuple(NORMALIZATIONS)}")
        check(
            self.padding is None or (np.isfinite(self.padding) and self.padding >= 0),
            f"padding: {self.padding!r} is not None or a finite number >= 0",
        )
        check(self.n_points > 0 or self.grid is not None, "nothing to sample: n_points is 0 and grid is None")
        check(isinstance(self.deepsdf, (bool, np.bool_)), f"deepsdf: {self.deepsdf!r} is not True or False")

    @property
    def effective_padding(self) -> float:
        return NORMALIZATIONS[self.normalize][0] if self.padding is None else float(self.padding)

    @property
    def volume(self) -> float:
        return NORMALIZATIONS[self.normalize][1]

    @property
    def n_uniform(self) -> int:
        """The uniform samples: the library's split (``proxima.training_sample_counts``)."""
        return proxima.training_sample_counts(int(self.n_points), float(self.uniform_fraction))[1]

    @property
    def n_near(self) -> int:
        return self.n_points - self.n_uniform

    def keys(self):
        """The arrays a complete output holds."""
        keys = ["points", "sdf", "scale", "offset", "volume", "n_near", "meta"]
        if self.kind == "occupancy":
            keys += ["occupancy", "occupancies", "loc"]
        if self.deepsdf:
            keys += ["pos", "neg"]
        if self.grid is not None:
            keys.append("grid")
        return keys

    def as_meta(self) -> Dict[str, Any]:
        """The options as the npz's meta records them (plain JSON values)."""
        d = asdict(self)
        d["n_points"] = int(self.n_points)
        d["grid"] = None if self.grid is None else int(self.grid)
        d["seed"] = int(self.seed)
        d["near_sigma"] = float(self.near_sigma)
        d["uniform_fraction"] = float(self.uniform_fraction)
        d["padding"] = self.effective_padding
        d.pop("compress")  # how the file is stored, not what it holds
        if not self.deepsdf:
            d.pop("deepsdf")  # absent from outputs written before the option existed
        return d


def memory_per_mesh(options: Options) -> Dict[str, int]:
    """The bytes one mesh's samples need at their peak, by the option that
    sizes them: ``{"n_points": ..., "grid": ...}`` (see BYTES_PER_SAMPLE and
    BYTES_PER_GRID_CELL)."""
    cells = int(options.grid) ** 3 if options.grid is not None else 0
    # DeepSDF's rows: 16 bytes a sample, twice (the rows, then split), and a mask.
    per_point = BYTES_PER_SAMPLE + (48 if options.deepsdf else 0)
    return {"n_points": int(options.n_points) * per_point, "grid": cells * BYTES_PER_GRID_CELL}


def check_memory(options: Options, meshes_at_once: int = 1) -> None:
    """Raises ``ValueError`` naming the option (``n_points`` or ``grid``, the
    larger part) when ``meshes_at_once`` meshes processed side by side in one
    process would need more than the memory budget, before any mesh is read:
    the library's check (``proxima.check_fits``, ``PROXIMA_MEMORY_BUDGET``), as
    every call of the package makes."""
    parts = memory_per_mesh(options)
    name = max(parts, key=parts.get)
    value = f"{options.n_points if name == 'n_points' else options.grid} per mesh"
    if meshes_at_once > 1:
        value += f" x {meshes_at_once} meshes at a time in one process (workers)"
    proxima.check_fits(name, value, int(meshes_at_once), sum(parts.values()))


def mesh_stem(path) -> str:
    """The file name without its mesh suffix (``.ply.gz`` counts as one)."""
    name = Path(path).name
    lower = name.lower()
    if lower.endswith(".gz"):
        name, lower = name[:-3], lower[:-3]
    for suffix in MESH_SUFFIXES:
        if lower.endswith(suffix):
            return name[: -len(suffix)]
    return Path(name).stem if "." in name else name


def is_mesh_file(path) -> bool:
    lower = str(path).lower()
    if lower.endswith(".gz"):
        lower = lower[:-3]
    return lower.endswith(MESH_SUFFIXES)


def mesh_seed(seed: int, name: str) -> np.random.SeedSequence:
    """The seed sequence of a mesh: the corpus seed and the CRC-32 of its
    name (UTF-8), never Python's ``hash`` (which changes per process)."""
    return np.random.SeedSequence([int(seed), zlib.crc32(name.encode("utf-8"))])


def sample_seed(seed: int, name: str) -> int:
    """The library's seed of a mesh's samples (``--seed`` of ``proxima sdf
    --sample``): the first 64-bit word of :func:`mesh_seed`'s state."""
    return int(mesh_seed(seed, name).generate_state(1, dtype=np.uint64)[0])


def normalization(vertices, used_vertices, normalize: str, padding: float):
    """``(scale, offset)`` with ``original = normalized * scale + offset``,
    float64, from the vertices that faces use (``used_vertices``, a mask)."""
    v = np.asarray(vertices, dtype=np.float64)
    used = v[np.asarray(used_vertices, dtype=bool)]
    if len(used) == 0:
        raise ValueError("the mesh has no face")
    lo, hi = used.min(axis=0), used.max(axis=0)
    offset = (lo + hi) / 2.0
    if normalize == "unit-sphere":
        extent = float(np.sqrt(((used - offset) ** 2).sum(axis=1).max()))
    elif normalize == "unit-cube":
        extent = float((hi - lo).max())
    else:
        raise ValueError(f"normalize: {normalize!r} is not one of {tuple(NORMALIZATIONS)}")
    scale = extent * (1.0 + padding)
    if not (np.isfinite(scale) and scale > 0.0):
        raise ValueError(f"the mesh is degenerate: its used vertices span {extent!r} (all at one point?)")
    return scale, offset


def normalize_vertices(vertices, scale: float, offset) -> np.ndarray:
    """``(vertices - offset) / scale`` in float64, rounded to float32 (the mesh's
    storage): the exact arithmetic a user repeats to rebuild the mesh."""
    v = np.asarray(vertices, dtype=np.float64)
    return ((v - np.asarray(offset, dtype=np.float64)) / float(scale)).astype(np.float32)


def output_path(output_dir, name) -> Path:
    return Path(output_dir) / f"{name}.npz"


def is_complete(path, options: Options) -> bool:
    """Whether ``path`` is a finished output of these options: it opens as an
    npz (the zip's directory is at its end: a truncated file fails), holds
    every key and its meta's options equal these."""
    try:
        with np.load(path, allow_pickle=False) as z:
            if not set(options.keys()) <= set(z.files):
                return False
            meta = json.loads(str(z["meta"]))
            return meta.get("format") == FORMAT_VERSION and meta.get("options") == options.as_meta()
    except Exception:  # noqa: BLE001 - anything unreadable is incomplete
        return False


def _attempts_path(out: Path) -> Path:
    return out.with_name(out.name[: -len(".npz")] + ATTEMPTS_SUFFIX)


def _count_attempt(out: Path) -> int:
    """This mesh's attempt number in this run (its file survives a worker that
    dies on it; the driver removes the files when a run starts and ends)."""
    path = _attempts_path(out)
    try:
        n = int(path.read_text() or 0)
    except (OSError, ValueError):
        n = 0
    path.write_text(str(n + 1))
    return n + 1


def _forget_attempts(out: Path) -> None:
    try:
        _attempts_path(out).unlink()
    except OSError:
        pass


def write_npz_atomic(path, arrays: Dict[str, np.ndarray], compress: bool = False) -> None:
    """``path`` appears complete or not at all: the arrays go to
    ``path.tmp-<random>``, which is fsynced and renamed over ``path``."""
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp-" + secrets.token_hex(6))
    try:
        with open(tmp, "xb") as f:
            (np.savez_compressed if compress else np.savez)(f, **arrays)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            tmp.unlink()
        except OSError:
            pass
        raise
    try:  # make the rename itself durable
        fd = os.open(path.parent, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
    except OSError:
        pass


def sample_mesh(path, name: str, options: Options, threads: Optional[int] = None, timings: Optional[dict] = None):
    """The arrays of one mesh's output (see the module's docstring)."""
    timings = {} if timings is None else timings
    t = time.perf_counter()
    mesh = proxima.load(path)
    if len(mesh) == 0:
        raise ValueError(f"{path}: the mesh has no face")
    vertices = mesh.vertices
    scale, offset = normalization(vertices, mesh.used_vertices, options.normalize, options.effective_padding)
    # Moved in place: the faces stay in the library (a mesh of mixed
    # polygons would otherwise make one array per face, and back).
    mesh.update_vertices(normalize_vertices(vertices, scale, offset))
    timings["load_s"] = time.perf_counter() - t

    t = time.perf_counter()
    seed = sample_seed(options.seed, name)
    timings["sample_s"] = time.perf_counter() - t

    # The points and their signed distances in one library call (the sdf
    # dominates): proxima sdf --sample's recipe.
    t = time.perf_counter()
    if options.n_points > 0:
        points, sdf = mesh.training_samples(
            int(options.n_points),
            near_sigma=float(options.near_sigma),
            uniform_fraction=float(options.uniform_fraction),
            cube=options.volume,
            seed=seed,
            threads=threads,
        )
    else:
        points, sdf = np.zeros((0, 3), np.float32), np.zeros(0, np.float32)
    if not np.all(np.isfinite(sdf)):
        raise ValueError(f"{path}: signed distances that are not finite ({int((~np.isfinite(sdf)).sum())} of {len(sdf)})")
    timings["sdf_s"] = time.perf_counter() - t

    arrays = {
        "points": points,
        "sdf": sdf,
        "scale": np.float64(scale),
        "offset": np.asarray(offset, dtype=np.float64),
        "volume": np.float64(options.volume),
        "n_near": np.int64(options.n_near),
    }
    if options.kind == "occupancy":
        arrays["occupancy"] = sdf < 0
        # Occupancy Networks' points.npz names (im2mesh's PointsField).
        arrays["occupancies"] = np.packbits(arrays["occupancy"])
        arrays["loc"] = arrays["offset"]
    if options.deepsdf:
        # DeepSDF's SdfSamples: (x, y, z, sdf) rows split by sign.
        rows = np.concatenate([points, sdf[:, None]], axis=1)
        arrays["pos"] = np.ascontiguousarray(rows[sdf >= 0])
        arrays["neg"] = np.ascontiguousarray(rows[sdf < 0])
    if options.grid is not None:
        t = time.perf_counter()
        arrays["grid"] = mesh.sdf_grid(int(options.grid), cube=options.volume, threads=threads)
        timings["grid_s"] = time.perf_counter() - t
    meta = {
        "format": FORMAT_VERSION,
        "name": name,
        "source": str(path),
        "options": options.as_meta(),
        "convention": "original = normalized * scale + offset",
        "grid_layout": "grid[i, j, k] at (x_i, x_j, x_k), x_i = -v + cell * (i + 0.5) in float32, v = float32(volume), cell = 2 v / N",
        "sample_seed": seed,
        "points_layout": "points[:n_near] near the surface, points[n_near:] uniform in [-volume, volume]^3",
        "occupancy": "sdf < 0",
        "sign": "winding number > 1/2 is inside (sdf < 0)",
        "proxima": proxima.__version__,
    }
    arrays["meta"] = np.array(json.dumps(meta, sort_keys=True))
    return arrays


def _error_status(path, name, error: BaseException, seconds: float) -> dict:
    return {
        "path": str(path),
        "name": name,
        "status": "failed",
        "samples": 0,
        "seconds": seconds,
        "error": f"{error}" or repr(error),
        "type": type(error).__name__,
    }


class WorkerDied(RuntimeError):
    """A mesh whose worker process died on every attempt (out of memory, killed)."""


def process_mesh(
    path, name: str, output_dir, options: Options, threads: Optional[int] = None, max_attempts: Optional[int] = None
) -> dict:
    """Samples one mesh into ``output_dir/name.npz`` unless it is complete
    there already. Never raises for the mesh's own errors: returns a status
    ``{"path", "name", "status" ("done", "skipped", "failed"), "samples",
    "seconds", "error", "type", "load_s", "sample_s", "sdf_s", "grid_s",
    "write_s"}``.

    ``max_attempts`` (the Ray engine, whose tasks are retried when their
    worker dies): the attempts at this mesh are counted in a file beside its
    output, and past ``max_attempts`` the mesh fails with ``WorkerDied``
    instead of killing one more worker."""
    start = time.perf_counter()
    out = output_path(output_dir, name)
    timings = {"load_s": 0.0, "sample_s": 0.0, "sdf_s": 0.0, "grid_s": 0.0, "write_s": 0.0}
    status = {"path": str(path), "name": name, "status": "skipped", "samples": 0, "seconds": 0.0, "error": "", "type": ""}
    try:
        if is_complete(out, options):
            status["seconds"] = time.perf_counter() - start
            status.update(timings)
            return status
        if max_attempts is not None:
            attempt = _count_attempt(out)
            if attempt > max_attempts:
                raise WorkerDied(
                    f"{path}: the worker process died on this mesh {attempt - 1} times "
                    "(out of memory, or killed); not retried"
                )
        arrays = sample_mesh(path, name, options, threads=threads, timings=timings)
        t = time.perf_counter()
        write_npz_atomic(out, arrays, compress=options.compress)
        timings["write_s"] = time.perf_counter() - t
    except (KeyboardInterrupt, SystemExit, GeneratorExit):
        raise
    except BaseException as error:  # noqa: BLE001 - includes pyo3's PanicException
        if max_attempts is not None:
            _forget_attempts(out)
        status = _error_status(path, name, error, time.perf_counter() - start)
        status.update(timings)
        return status
    if max_attempts is not None:
        _forget_attempts(out)
    status["status"] = "done"
    status["samples"] = len(arrays["points"]) + (int(options.grid) ** 3 if options.grid is not None else 0)
    status["seconds"] = time.perf_counter() - start
    status.update(timings)
    return status

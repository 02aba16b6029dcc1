"""Signed-distance and occupancy samples for every mesh of a corpus.

>>> from proxima.dataset import sample_corpus
>>> summary = sample_corpus("meshes/**/*.obj", "samples/", n_points=250_000)   # doctest: +SKIP

or from a shell::

    python -m proxima.dataset meshes/ samples/ --points 250000 --kind occupancy --grid 64

Each mesh ``M`` gives ``samples/<name>.npz`` (layout: :mod:`proxima.dataset.sampling`):
``points`` float32 (n, 3), ``sdf`` float32 (n,), ``occupancy`` bool (n,) for
``kind="occupancy"``, ``grid`` float32 (N, N, N) with ``grid=N``, and the
normalization ``scale``, ``offset`` with ``original = normalized * scale + offset``.

Engines: ``engine="ray"`` (the default; ``pip install "proxima[ray]"``) runs on
Ray Data: ``address=None`` starts a local Ray instance (or uses the one this
process initialized already), ``address="auto"`` or ``"ray://host:port"``
joins a cluster, whose nodes must all see the input files and
``output_dir`` (a shared file system) and have proxima installed.
``engine="local"`` uses this machine's cores only, without Ray. Both write the
same arrays, bit for bit: a mesh's output depends only on its file, its name
and the options.

Names: ``<stem>.npz`` (``bunny.obj`` gives ``bunny.npz``; ``.ply.gz`` counts as
one suffix). When several inputs share a stem, each of them is named
``<stem>-<8 hex digits>``, the digits from the SHA-1 of its path relative to the
inputs' common folder (POSIX separators), so names do not depend on the order
of the inputs or on where the corpus is mounted.

Resuming: a mesh whose ``<name>.npz`` is complete (it opens, holds every key and
was made with the same options) is skipped; outputs are written to
``<name>.npz.tmp-<random>`` and renamed, so a killed job leaves no partial
output; leftover temporary files are removed when a job starts and ends (so
run one job per output folder at a time).

Failures: each mesh that fails (cannot be read, malformed, no face, a worker
that died on it every retry) adds a line ``{"path", "name", "error", "type",
"time"}`` to ``output_dir/failures.jsonl`` and the job goes on; successful meshes
add none. A later run retries the failed meshes (they have no output).
"""

from __future__ import annotations

import glob as _glob
import hashlib
import json
import os
import sys
import time
from pathlib import Path
from typing import Iterable, List, Optional, Sequence, Tuple, Union

import proxima

from .sampling import (
    ATTEMPTS_SUFFIX,
    KINDS,
    NORMALIZATIONS,
    TMP_MARKER,
    Options,
    check_memory,
    is_complete,
    is_mesh_file,
    mesh_seed,
    mesh_stem,
    normalization,
    normalize_vertices,
    output_path,
    process_mesh,
    sample_mesh,
    sample_seed,
)

__all__ = [
    "sample_corpus",
    "resolve_inputs",
    "mesh_names",
    "Options",
    "check_memory",
    "process_mesh",
    "sample_mesh",
    "normalization",
    "normalize_vertices",
    "mesh_seed",
    "sample_seed",
    "is_complete",
    "KINDS",
    "NORMALIZATIONS",
]

PathLike = Union[str, os.PathLike]

#: The per-mesh timings a summary keeps.
_TIMING_KEYS = ("name", "status", "samples", "seconds", "load_s", "sample_s", "sdf_s", "grid_s", "write_s")

#: Corpora up to this many meshes get per-mesh timings in the summary (beyond,
#: only their sums: the driver's memory).
PER_MESH_LIMIT = 100_000


def _has_magic(text: str) -> bool:
    return any(c in text for c in "*?[")


def _expand(entry: PathLike) -> List[Path]:
    text = os.fspath(entry)
    if _has_magic(text):
        return sorted(Path(p) for p in _glob.glob(text, recursive=True) if os.path.isfile(p))
    path = Path(text)
    if path.is_dir():
        return sorted(p for p in path.rglob("*") if p.is_file() and is_mesh_file(p))
    if is_mesh_file(path):
        return [path]  # a missing mesh file is the mesh's failure, not the corpus's
    if path.is_file():  # a list of paths, one a line ('#' comments), relative to the list's folder
        out = []
        for line in path.read_text(encoding="utf-8").splitlines():
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            item = Path(line)
            out.append(item if item.is_absolute() else path.parent / item)
        return out
    raise FileNotFoundError(f"{text}: no such file, folder or matching glob")


def resolve_inputs(inputs: Union[PathLike, Iterable[PathLike]]) -> List[Path]:
    """The mesh files that ``inputs`` names: a glob (``**`` recursive), a folder
    (its mesh files, recursively), a mesh file, a text file listing paths (one
    a line), or a list of these. Absolute, without duplicates, sorted."""
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    seen = {}
    for entry in inputs:
        for path in _expand(entry):
            absolute = Path(os.path.abspath(path))
            seen.setdefault(str(absolute), absolute)
    return [seen[k] for k in sorted(seen)]


def mesh_names(paths: Sequence[Path]) -> List[str]:
    """The output name of each path (see the module's docstring: the stem, and
    a hash of the relative path where stems collide)."""
    stems = [mesh_stem(p) for p in paths]
    counts = {}
    for stem in stems:
        counts[stem] = counts.get(stem, 0) + 1
    root = os.path.commonpath([os.path.dirname(str(p)) for p in paths]) if paths else ""
    names = []
    for path, stem in zip(paths, stems):
        if counts[stem] == 1:
            names.append(stem)
        else:
            relative = Path(os.path.relpath(str(path), root)).as_posix()
            names.append(f"{stem}-{hashlib.sha1(relative.encode('utf-8')).hexdigest()[:8]}")
    if len(set(names)) != len(names):  # a stem-hash equal to another file's stem: vanishingly rare
        raise ValueError("mesh names collide even after hashing; rename the files")
    return names


def _remove_tmp_files(output_dir: Path) -> int:
    """Removes the temporary outputs and attempt counts of earlier runs."""
    removed = 0
    for path in [*output_dir.glob(f"*{TMP_MARKER}*"), *output_dir.glob(f"*{ATTEMPTS_SUFFIX}")]:
        try:
            path.unlink()
            removed += 1
        except OSError:
            pass
    return removed


def sample_corpus(
    inputs,
    output_dir: PathLike,
    n_points: int = 250_000,
    near_sigma: float = 0.01,
    grid: Optional[int] = None,
    kind: str = "sdf",
    seed: int = 0,
    address: Optional[str] = None,
    *,
    engine: str = "ray",
    normalize: Optional[str] = None,
    padding: Optional[float] = None,
    uniform_fraction: float = 0.1,
    workers: Optional[int] = None,
    threads: Optional[int] = None,
    local_pool: str = "thread",
    compress: bool = False,
    deepsdf: bool = False,
    max_task_retries: int = 3,
    progress: bool = True,
) -> dict:
    """Samples every mesh of ``inputs`` into ``output_dir/<name>.npz``.

    ``inputs``: a glob, a folder, a mesh file, a text file listing paths, or a
    list of these. ``n_points`` points per mesh, ``1 - uniform_fraction`` of
    them near the surface (gaussian offsets of ``near_sigma``, normalized
    units), the rest uniform in the normalized sampling cube; ``sdf`` at each;
    ``kind="occupancy"`` adds ``occupancy = sdf < 0``; ``grid=N`` adds an
    (N, N, N) grid of signed distances. ``normalize``: ``"unit-sphere"``
    (DeepSDF) or ``"unit-cube"`` (Occupancy Networks); ``None`` picks
    unit-sphere for ``kind="sdf"`` and unit-cube for ``"occupancy"``.
    ``padding``: ``None`` for the normalization's default (0.03 unit-sphere,
    0 unit-cube). ``seed``: with the mesh's name, fixes its samples.
    ``kind="occupancy"`` outputs also hold Occupancy Networks' names
    (``occupancies`` packed, ``loc``); ``deepsdf=True`` adds DeepSDF's
    ``pos``/``neg`` arrays (16 more bytes a sample), so that either project's
    loader reads the files as they are.

    ``engine``: ``"ray"`` or ``"local"``. ``workers`` meshes at a time (Ray:
    actors; default: the CPUs divided by ``threads``), each queried with
    ``threads`` threads (default 1: meshes in parallel beat threads in one
    mesh). ``local_pool``: ``"thread"`` or ``"process"``. ``max_task_retries``
    (Ray): how many times a mesh whose worker died is retried.

    Returns (and the command prints) a summary: ``meshes``, ``done``,
    ``skipped``, ``failed``, ``samples`` (signed distances computed:
    points and grid cells), ``seconds`` (wall clock, Ray's start included),
    ``samples_per_second`` (and ``_per_core``: over ``workers * threads``),
    ``mesh_seconds`` (summed over the meshes: in total, to load and
    normalize, sample, compute ``sdf``, the grid, and write), and
    ``per_mesh``: each mesh's status and those timings (for corpora of up to
    100,000 meshes; empty beyond).
    """
    start = time.perf_counter()
    if normalize is None:
        normalize = "unit-cube" if kind == "occupancy" else "unit-sphere"
    options = Options(
        n_points=int(n_points),
        near_sigma=float(near_sigma),
        uniform_fraction=float(uniform_fraction),
        grid=None if grid is None else int(grid),
        kind=kind,
        seed=int(seed),
        normalize=normalize,
        padding=None if padding is None else float(padding),
        compress=bool(compress),
        deepsdf=deepsdf,
    )
    if engine not in ("ray", "local"):
        raise ValueError(f"engine: {engine!r} is not 'ray' or 'local'")
    cap = proxima.max_threads()
    if threads is not None and not 1 <= int(threads) <= cap:
        raise ValueError(f"threads: {threads!r} is not between 1 and {cap} (4 per core on this machine, at least 8)")
    threads = 1 if threads is None else int(threads)
    if workers is not None:
        workers = int(workers)
        # Ray's actors may wait for an autoscaling cluster to grow; local
        # workers are this process' threads or child processes.
        if workers < 1 or (engine == "local" and workers > cap):
            bound = f"between 1 and {cap} for the local engine" if engine == "local" else ">= 1"
            raise ValueError(f"workers: {workers!r} is not {bound}")
    if local_pool not in ("thread", "process"):
        raise ValueError(f"local_pool: {local_pool!r} is not 'thread' or 'process'")
    # Each Ray actor and each local process holds one mesh at a time; local
    # threads share this process.
    at_once = 1
    if engine == "local" and local_pool == "thread":
        at_once = workers if workers is not None else max(1, (os.cpu_count() or 1) // threads)
    check_memory(options, at_once)

    paths = resolve_inputs(inputs)
    names = mesh_names(paths)
    items: List[Tuple[str, str]] = [(str(p), n) for p, n in zip(paths, names)]
    output_dir = Path(output_dir)
    output_dir.mkdir(parents=True, exist_ok=True)
    _remove_tmp_files(output_dir)
    failures_path = output_dir / "failures.jsonl"

    counts = {"done": 0, "skipped": 0, "failed": 0}
    samples = 0
    per_mesh = []
    keep_per_mesh = len(items) <= PER_MESH_LIMIT
    timings = dict.fromkeys(_TIMING_KEYS[3:], 0.0)

    def on_result(status: dict) -> None:
        nonlocal samples
        kind_ = status["status"]
        counts[kind_] = counts.get(kind_, 0) + 1
        samples += int(status.get("samples", 0))
        for key in timings:
            timings[key] += float(status.get(key, 0.0))
        if keep_per_mesh:
            per_mesh.append({k: status.get(k, 0.0) for k in _TIMING_KEYS})
        if kind_ == "failed":
            record = {
                "path": status["path"],
                "name": status["name"],
                "error": status.get("error", ""),
                "type": status.get("type", ""),
                "time": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            }
            with open(failures_path, "a", encoding="utf-8") as f:
                f.write(json.dumps(record) + "\n")

    started_ray = False
    if engine == "local":
        from .engines import run_local

        if workers is None:
            workers = max(1, (os.cpu_count() or 1) // threads)
        run_local(items, output_dir, options, on_result, workers=int(workers), threads=threads, pool=local_pool)
    else:
        try:
            import ray  # noqa: F401
            import ray.data  # noqa: F401
        except ImportError as error:
            raise ImportError(
                'engine="ray" needs Ray Data: pip install "proxima[ray]" (or ray[data]), '
                'or use engine="local" (--engine local)'
            ) from error
        from .engines import ray_cpus, ray_init, run_ray

        started_ray = ray_init(address)
        try:
            if workers is None:
                workers = max(1, ray_cpus() // threads)
            missing = run_ray(
                items, output_dir, options, on_result, workers=int(workers), threads=threads,
                max_task_retries=int(max_task_retries), progress=progress,
            )
            for path, name in missing:
                if is_complete(output_path(output_dir, name), options):
                    on_result({"path": path, "name": name, "status": "done", "samples": 0, "seconds": 0.0})
                else:
                    on_result({
                        "path": path, "name": name, "status": "failed", "samples": 0, "seconds": 0.0,
                        "type": "WorkerDied",
                        "error": "no result from Ray: the task of this mesh failed (its worker died: out of memory, or killed)",
                    })
        finally:
            if started_ray:
                import ray

                ray.shutdown()
    _remove_tmp_files(output_dir)

    seconds = time.perf_counter() - start
    per_mesh.sort(key=lambda m: m["name"])
    rate = samples / seconds if seconds > 0 else 0.0
    return {
        "meshes": len(items),
        **counts,
        "samples": samples,
        "seconds": seconds,
        "samples_per_second": rate,
        "samples_per_second_per_core": rate / (int(workers) * threads),
        "mesh_seconds": timings,
        "engine": engine,
        "workers": int(workers),
        "threads": threads,
        "normalize": normalize,
        "output_dir": str(output_dir),
        "failures": str(failures_path) if counts["failed"] else None,
        "per_mesh": per_mesh,
    }


def _print_summary(summary: dict, file=sys.stdout) -> None:
    brief = {k: v for k, v in summary.items() if k != "per_mesh"}
    brief["mesh_seconds"] = {k: round(v, 3) for k, v in brief["mesh_seconds"].items()}
    print(json.dumps(brief, indent=2), file=file)
    done = [m for m in summary["per_mesh"] if m["status"] == "done"]
    if done:
        print("slowest meshes (seconds: load+normalize / sample / sdf / grid / write):", file=file)
        for m in sorted(done, key=lambda m: -m["seconds"])[:5]:
            print(
                f"  {m['name']}: {m['seconds']:.3f} s ({m['load_s']:.3f} / {m['sample_s']:.3f} / "
                f"{m['sdf_s']:.3f} / {m['grid_s']:.3f} / {m['write_s']:.3f}), {m['samples']} samples",
                file=file,
            )

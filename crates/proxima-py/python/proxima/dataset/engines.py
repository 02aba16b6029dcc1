"""The engines that run :func:`proxima.dataset.sampling.process_mesh` over a
corpus: Ray Data (an actor pool, on one machine or a cluster) and a local
pool (threads or processes, no Ray). Each calls ``on_result(status)`` in the
driver as meshes finish; the driver alone writes ``failures.jsonl``.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from .sampling import Options, process_mesh

Item = Tuple[str, str]  # (path, name)
STATUS_KEYS = ("path", "name", "status", "samples", "seconds", "error", "type", "load_s", "sample_s", "sdf_s", "grid_s", "write_s")


# --- local ---------------------------------------------------------------------------


def _process_local(path, name, output_dir, options_dict, threads):
    return process_mesh(path, name, output_dir, Options(**options_dict), threads=threads)


def run_local(
    items: Sequence[Item],
    output_dir: str,
    options: Options,
    on_result: Callable[[dict], None],
    workers: int,
    threads: Optional[int],
    pool: str = "thread",
) -> None:
    """``workers`` meshes at a time in a thread pool (proxima releases the GIL)
    or a process pool (``spawn``: a forked child would inherit a dead native
    thread pool), ``threads`` native threads per worker (proxima keeps its
    native pools per calling Python thread, so each worker has its own)."""
    options_dict = {k: getattr(options, k) for k in Options.__dataclass_fields__}
    if pool == "thread":
        executor = cf.ThreadPoolExecutor(max_workers=workers, thread_name_prefix="proxima-dataset")
    elif pool == "process":
        executor = cf.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"))
    else:
        raise ValueError(f"pool: {pool!r} is not 'thread' or 'process'")
    pending: Dict[cf.Future, Item] = {}
    queue = iter(items)
    try:
        while True:
            # A bounded window of submitted meshes (a corpus may hold millions).
            while len(pending) < 2 * workers:
                item = next(queue, None)
                if item is None:
                    break
                pending[executor.submit(_process_local, item[0], item[1], str(output_dir), options_dict, threads)] = item
            if not pending:
                break
            finished, _ = cf.wait(pending, return_when=cf.FIRST_COMPLETED)
            for future in finished:
                path, name = pending.pop(future)
                try:
                    status = future.result()
                except Exception as error:  # a dead worker process (BrokenProcessPool)
                    status = {"path": path, "name": name, "status": "failed", "samples": 0, "seconds": 0.0, "error": str(error) or repr(error), "type": type(error).__name__}
                on_result(status)
    except BaseException:
        executor.shutdown(wait=False, cancel_futures=True)
        raise
    executor.shutdown(wait=True)


# --- Ray -----------------------------------------------------------------------------


class MeshSampler:
    """The Ray Data actor: one mesh per batch, its structures built, queried
    with the actor's ``threads`` and dropped before the next; the actor keeps
    only its options (and the native thread pool of that size)."""

    def __init__(self, output_dir: str, options: dict, threads: int, max_attempts: int):
        self.output_dir = output_dir
        self.options = Options(**options)
        self.threads = threads
        self.max_attempts = max_attempts

    def __call__(self, batch: Dict[str, np.ndarray]) -> Dict[str, np.ndarray]:
        rows = [
            process_mesh(
                str(path), str(name), self.output_dir, self.options, threads=self.threads, max_attempts=self.max_attempts
            )
            for path, name in zip(batch["path"], batch["name"])
        ]
        return {key: np.array([row.get(key, _default(key)) for row in rows]) for key in STATUS_KEYS}


def _default(key):
    return 0.0 if key.endswith("_s") or key == "seconds" else ("" if key not in ("samples",) else 0)


def _proxima_env() -> Dict[str, str]:
    """The driver's ``PROXIMA_*`` variables (memory budget, load limits,
    testing hooks), passed to the actors: on a cluster they do not inherit
    the driver's environment."""
    return {k: v for k, v in os.environ.items() if k.startswith("PROXIMA_")}


def ray_init(address: Optional[str]) -> bool:
    """``ray.init(address=address)`` unless Ray is initialized already (then
    its instance is used, whatever ``address`` says). Returns whether this
    call started it (the caller shuts it down)."""
    import ray

    if ray.is_initialized():
        return False
    ray.init(address=address)
    return True


def ray_cpus() -> int:
    import ray

    return max(1, int(ray.cluster_resources().get("CPU", 1)))


def run_ray(
    items: Sequence[Item],
    output_dir: str,
    options: Options,
    on_result: Callable[[dict], None],
    workers: int,
    threads: int,
    max_task_retries: int = 3,
    progress: bool = True,
) -> List[Item]:
    """Ray Data: the meshes as a dataset, ``map_batches`` on an actor pool of
    ``workers`` actors of ``threads`` CPUs each, one mesh per batch; statuses
    consumed as they stream back.

    Fault tolerance: Ray Data restarts a dead actor and retries its task
    (its defaults for actor pools, ``max_restarts=-1`` and
    ``max_task_retries=-1``; passing them to ``map_batches`` is deprecated
    since Ray 2.60 and removed in 2.64), and the atomic write makes a redone
    mesh harmless. The retries are bounded here instead: the actor counts its
    attempts at each mesh (``NAME.npz.attempts``) and past
    ``max_task_retries + 1`` returns a ``WorkerDied`` failure. A block Ray
    still gives up on does not abort the corpus (``max_errored_blocks=-1``):
    its meshes come back as items without a row (the caller records them)."""
    import ray
    from ray.data import DataContext

    context = DataContext.get_current()
    saved = (context.max_errored_blocks, context.enable_progress_bars)
    # A block whose task failed every retry (a mesh that kills its worker each
    # time) is reported by the caller, not allowed to abort the whole corpus.
    context.max_errored_blocks = -1
    context.enable_progress_bars = progress
    seen = set()
    try:
        # One block per mesh up to 10,000 meshes (fine-grained balancing and
        # retries); beyond, meshes share blocks.
        blocks = max(1, min(len(items), max(10_000, 16 * workers)))
        dataset = ray.data.from_items([{"path": p, "name": n} for p, n in items], override_num_blocks=blocks)
        dataset = dataset.map_batches(
            MeshSampler,
            fn_constructor_kwargs={
                "output_dir": str(output_dir),
                "options": {k: getattr(options, k) for k in Options.__dataclass_fields__},
                "threads": threads,
                "max_attempts": max_task_retries + 1,
            },
            batch_size=1,
            batch_format="numpy",
            compute=ray.data.ActorPoolStrategy(size=workers),
            num_cpus=threads,
            runtime_env={"env_vars": _proxima_env()},
        )
        for row in dataset.iter_rows():
            status = {key: _plain(row[key]) for key in STATUS_KEYS if key in row}
            seen.add(status["name"])
            on_result(status)
    finally:
        context.max_errored_blocks, context.enable_progress_bars = saved
    return [item for item in items if item[1] not in seen]


def _plain(value):
    """A numpy scalar of a row as a Python value (JSON-ready)."""
    if isinstance(value, np.generic):
        return value.item()
    return value

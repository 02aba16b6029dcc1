"""What the benchmark scripts share: timing a piece of work, and writing the
report (printed, and to ``--out`` when given)."""

import json
import time
from pathlib import Path


def timed(reps, work):
    """The fastest of ``reps`` runs of ``work()`` in seconds, and the
    result of the last run."""
    best, result = float("inf"), None
    for _ in range(reps):
        start = time.perf_counter()
        result = work()
        best = min(best, time.perf_counter() - start)
    return best, result


def fastest(reps, work):
    """The fastest of ``reps`` runs of ``work()``, in seconds."""
    return timed(reps, work)[0]


def report(values, out=None):
    """Prints ``values`` as indented JSON, and writes it to ``out``."""
    text = json.dumps(values, indent=2)
    print(text)
    if out:
        Path(out).write_text(text + "\n")

"""Fault injection for the dataset's Ray tests, kept out of the package.

``PROXIMA_DATASET_TEST_CRASH=NAME=MARKER_PATH`` makes the process that writes
NAME's output exit abruptly (``os._exit``) after writing its temporary file,
before the rename, the first time only (creating the marker file); ``NAME``
alone, every time. It acts in processes where :func:`install` ran: the Ray
actors run in processes of their own, so :func:`site_dir` makes a folder whose
``sitecustomize`` installs it at start-up in every Python process that has the
variable (the engines pass ``PROXIMA_*`` variables on to their actors) and
that folder on ``PYTHONPATH``.
"""

import os
import sys
from pathlib import Path

CRASH_ENV = "PROXIMA_DATASET_TEST_CRASH"


def crash_point(name: str) -> None:
    spec = os.environ.get(CRASH_ENV)
    if not spec:
        return
    target, _, marker = spec.partition("=")
    if target != name:
        return
    if marker:
        try:
            fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:
            return
        os.write(fd, f"{os.getpid()}\n".encode())
        os.close(fd)
    os._exit(70)


class _CrashingOs:
    """The ``os`` module, but ``replace`` (the rename that publishes an output,
    ``NAME.npz.tmp-<hex>`` -> ``NAME.npz``) passes :func:`crash_point` first."""

    def __init__(self, real):
        self._real = real

    def __getattr__(self, attribute):
        return getattr(self._real, attribute)

    def replace(self, src, dst, *args, **kwargs):
        name = Path(dst).name
        if name.endswith(".npz"):
            crash_point(name[: -len(".npz")])
        return self._real.replace(src, dst, *args, **kwargs)


def install() -> None:
    """Makes this process's dataset writes pass :func:`crash_point`."""
    from proxima.dataset import sampling

    if not isinstance(sampling.os, _CrashingOs):
        sampling.os = _CrashingOs(sampling.os)


def site_dir(folder) -> Path:
    """``folder`` with a ``sitecustomize.py`` that runs :func:`install` in any
    Python process started with :data:`CRASH_ENV` set (put ``folder`` on
    ``PYTHONPATH``)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    here = str(Path(__file__).resolve().parent)
    (folder / "sitecustomize.py").write_text(
        "import os, sys\n"
        f"if os.environ.get({CRASH_ENV!r}):\n"
        f"    sys.path.insert(0, {here!r})\n"
        "    import dataset_crash\n"
        "    dataset_crash.install()\n"
    )
    return folder

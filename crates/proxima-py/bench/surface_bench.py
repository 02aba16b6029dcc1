#!/usr/bin/env python3
"""What comes with an answer (issue 38): the cost of the ``return_*``
options, one thread, in one process, against the same calls without them.

    surface_bench.py [--mesh FILE] [--n N] [--reps R] [--out FILE]

Workload: the mesh (default the 871k-triangle dragon of ../shared/data),
N points near its surface (``sample_near_surface``, sigma 1% of the
diagonal) and N rays from points around it towards its centre (seeded).
Rows, each the fastest of R runs, with the structures built first:

- ``closest_points`` plain, and with ``return_barycentric``,
  ``return_feature`` and ``return_normal`` all on;
- ``cast_rays`` plain, and with the three options on;
- ``signed_distance`` plain, and with ``return_gradient``.

Output JSON: seconds per row and the ratio of each option row to its plain
row (the issue's bound: 1.15).
"""

import argparse
from pathlib import Path

import numpy as np

import proxima
from _timing import fastest, report

DRAGON = Path(__file__).resolve().parents[4] / "shared" / "data" / "dragon_vrip.ply.gz"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--mesh", default=str(DRAGON))
    parser.add_argument("--n", type=int, default=100_000)
    parser.add_argument("--reps", type=int, default=5)
    parser.add_argument("--out")
    args = parser.parse_args()

    mesh = proxima.load(args.mesh)
    points = mesh.sample_near_surface(args.n, sigma=0.01, seed=1)
    lo, hi = mesh.bounds
    rng = np.random.default_rng(2)
    origins = (lo + (hi - lo) * (rng.random((args.n, 3)) * 1.4 - 0.2)).astype(np.float32)
    directions = ((lo + hi) / 2 - origins).astype(np.float32)
    all_on = dict(return_barycentric=True, return_feature=True, return_normal=True)
    # Build every structure (and the vertex normals) before timing.
    mesh.closest_points(points[:10], **all_on)
    mesh.cast_rays(origins[:10], directions[:10], **all_on)
    mesh.signed_distance(points[:10], return_gradient=True)

    rows = {
        "closest_points": lambda: mesh.closest_points(points, threads=1),
        "closest_points+all": lambda: mesh.closest_points(points, threads=1, **all_on),
        "cast_rays": lambda: mesh.cast_rays(origins, directions, threads=1),
        "cast_rays+all": lambda: mesh.cast_rays(origins, directions, threads=1, **all_on),
        "signed_distance": lambda: mesh.signed_distance(points, threads=1),
        "signed_distance+gradient": lambda: mesh.signed_distance(points, threads=1, return_gradient=True),
    }
    seconds = {name: fastest(args.reps, work) for name, work in rows.items()}
    ratios = {
        name: seconds[name] / seconds[name.split("+")[0]] for name in seconds if "+" in name
    }
    report({"mesh": args.mesh, "n": args.n, "reps": args.reps, "seconds": seconds, "ratios": ratios}, args.out)


if __name__ == "__main__":
    main()

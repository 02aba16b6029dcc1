#!/usr/bin/env python3
"""Point clouds (issue 39): proxima.Points against scipy's cKDTree, and
pykdtree where it imports, in one process per run, one thread each.

    points_bench.py [--points N] [--queries Q] [--reps R] [--out FILE]

Workload: N points uniform in the unit cube and Q query points uniform in
the same cube (seeded), float32 for proxima and float64 for scipy (the
same values). Rows:

- k-nearest, k = 1, 8, 32: `Points.k_nearest(q, k, threads=1)` against
  `cKDTree.query(q, k, workers=1)` (and pykdtree's `query`);
- radius search with about 16 and 128 neighbours per query:
  `Points.within(q, r, threads=1)` (compressed rows) against
  `cKDTree.query_ball_point(q, r, workers=1, return_sorted=False)` plus
  the numpy work to put its lists in the same compressed rows;
- Chamfer between two clouds of min(N, 100k) points: `proxima.chamfer`
  against a cKDTree-based numpy implementation (two trees, two queries).

Structures are built before timing (build times are reported apart). Each
row is the fastest of R runs. Output JSON: seconds per row and the ratio.
"""

import argparse
import time

import numpy as np
from scipy.spatial import cKDTree

import proxima
from _timing import fastest, report

try:
    from pykdtree.kdtree import KDTree as PyKDTree
except ImportError:  # optional peer
    PyKDTree = None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--queries", type=int, default=1_000_000)
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--out")
    args = parser.parse_args()
    rng = np.random.default_rng(39)
    points = rng.random((args.points, 3), dtype=np.float32)
    queries = rng.random((args.queries, 3), dtype=np.float32)
    points64, queries64 = points.astype(np.float64), queries.astype(np.float64)
    rows = []

    start = time.perf_counter()
    cloud = proxima.Points(points, threads=1)
    build = {"proxima": time.perf_counter() - start}
    start = time.perf_counter()
    tree = cKDTree(points64)
    build["scipy"] = time.perf_counter() - start
    if PyKDTree is not None:
        start = time.perf_counter()
        pyk = PyKDTree(points)
        build["pykdtree"] = time.perf_counter() - start

    for k in (1, 8, 32):
        ours = fastest(args.reps, lambda: cloud.k_nearest(queries, k, threads=1))
        theirs = fastest(args.reps, lambda: tree.query(queries64, k, workers=1))
        row = {"query": f"k_nearest k={k}", "proxima": ours, "scipy": theirs, "ratio_scipy": theirs / ours}
        if PyKDTree is not None:
            row["pykdtree"] = fastest(args.reps, lambda: pyk.query(queries, k))
            row["ratio_pykdtree"] = row["pykdtree"] / ours
        rows.append(row)

    for neighbours in (16, 128):
        # The radius of a ball holding that many points on average.
        r = (3 * neighbours / (4 * np.pi * args.points)) ** (1 / 3)

        def scipy_rows():
            lists = tree.query_ball_point(queries64, r, workers=1, return_sorted=False)
            counts = np.fromiter((len(x) for x in lists), np.int64, len(lists))
            offsets = np.concatenate([[0], np.cumsum(counts)])
            index = np.fromiter((j for x in lists for j in x), np.int64, offsets[-1])
            return offsets, index

        ours = fastest(args.reps, lambda: cloud.within(queries, r, threads=1))
        theirs = fastest(args.reps, scipy_rows)
        found = int(cloud.count_within(queries, r, threads=1).sum())
        rows.append(
            {
                "query": f"within ~{neighbours}",
                "r": r,
                "neighbours": found / args.queries,
                "proxima": ours,
                "scipy": theirs,
                "ratio_scipy": theirs / ours,
            }
        )

    n = min(args.points, 100_000)
    a, b = points[:n], queries[:n]
    a64, b64 = a.astype(np.float64), b.astype(np.float64)

    def scipy_chamfer():
        da, _ = cKDTree(b64).query(a64, 1, workers=1)
        db, _ = cKDTree(a64).query(b64, 1, workers=1)
        return (da**2).mean() + (db**2).mean()

    ours = fastest(args.reps, lambda: proxima.chamfer(a, b, threads=1))
    theirs = fastest(args.reps, scipy_chamfer)
    rows.append({"query": f"chamfer {n}x{n}", "proxima": ours, "scipy": theirs, "ratio_scipy": theirs / ours})

    out = {"points": args.points, "queries": args.queries, "build": build, "rows": rows}
    report(out, args.out)


if __name__ == "__main__":
    main()

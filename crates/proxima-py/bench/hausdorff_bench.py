#!/usr/bin/env python3
"""The Hausdorff distance between two meshes' surfaces (issue 39): proxima's
bounds against the peers' sampling, each engine in its own process.

    hausdorff_bench.py A B --engine proxima [--tolerance 1e-4] --export AB.npz
    hausdorff_bench.py AB.npz --engine pymeshlab|trimesh|meshlib [--samples N]

`proxima` loads the two meshes (any format proxima reads, or the names
`ico1m` and `ico100k` for proxima's noisy icospheres), writes their
float32 vertices and triangles to ``--export`` for the peers, and times
``proxima.hausdorff(a, b, tolerance=T * diagonal)`` on one thread, the
faces' trees built inside the timing (a fresh Mesh each run). The peers
read the exported arrays and time, in both directions:

- pymeshlab: ``get_hausdorff_distance`` with ``samplenum=N`` (vertices,
  edges and faces sampled, MeshLab's default sampling);
- trimesh: ``sample_surface(N)`` plus the mesh's vertices, then
  ``proximity.closest_point`` on the other mesh;
- meshlib: ``findMaxDistanceSq``, the largest distance from a vertex of
  either mesh to the other (vertices only).

A sampler's answer is a lower bound: compare it with proxima's bracket.
Each engine prints one JSON line (seconds: fastest of ``--reps``).
"""

import argparse
import json
import os

import numpy as np

from _timing import timed as fastest


def run_proxima(args):
    import proxima

    named = {"ico1m": (224, 1), "ico100k": (71, 1)}

    def load(name):
        if name in named:
            return proxima.noisy_icosphere(*named[name])
        return proxima.load(name)

    a, b = load(args.inputs[0]), load(args.inputs[1])
    va, fa, vb, fb = a.vertices, np.asarray(a.faces), b.vertices, np.asarray(b.faces)
    if args.export:
        np.savez(args.export, va=va, fa=fa, vb=vb, fb=fb)
    diagonal = max(np.linalg.norm(np.ptp(v, axis=0)) for v in (va, vb))
    tolerance = args.tolerance * diagonal

    def work():
        return proxima.hausdorff(proxima.Mesh(va, fa), proxima.Mesh(vb, fb), tolerance=tolerance, threads=1)

    seconds, h = fastest(args.reps, work)
    return {"lower": h.lower, "upper": h.upper, "tolerance": float(tolerance), "seconds": seconds}


def arrays(path):
    data = np.load(path)
    return data["va"], data["fa"], data["vb"], data["fb"]


def run_pymeshlab(args):
    import pymeshlab

    va, fa, vb, fb = arrays(args.inputs[0])

    def work():
        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(vertex_matrix=va.astype(np.float64), face_matrix=fa.astype(np.int32)))
        ms.add_mesh(pymeshlab.Mesh(vertex_matrix=vb.astype(np.float64), face_matrix=fb.astype(np.int32)))
        forward = ms.get_hausdorff_distance(sampledmesh=0, targetmesh=1, samplenum=args.samples)
        backward = ms.get_hausdorff_distance(sampledmesh=1, targetmesh=0, samplenum=args.samples)
        return max(forward["max"], backward["max"])

    seconds, value = fastest(args.reps, work)
    return {"value": value, "samples": args.samples, "seconds": seconds}


def run_trimesh(args):
    import trimesh

    va, fa, vb, fb = arrays(args.inputs[0])

    def one_way(src, dst):
        points, _ = trimesh.sample.sample_surface(src, args.samples, seed=1)
        points = np.concatenate([points, src.vertices])
        _, distance, _ = trimesh.proximity.closest_point(dst, points)
        return distance.max()

    def work():
        a = trimesh.Trimesh(va.astype(np.float64), fa, process=False)
        b = trimesh.Trimesh(vb.astype(np.float64), fb, process=False)
        return max(one_way(a, b), one_way(b, a))

    seconds, value = fastest(args.reps, work)
    return {"value": value, "samples": args.samples, "seconds": seconds}


def run_meshlib(args):
    import meshlib.mrmeshnumpy as mn
    import meshlib.mrmeshpy as mr

    va, fa, vb, fb = arrays(args.inputs[0])

    def work():
        a = mn.meshFromFacesVerts(fa.astype(np.int32), va.astype(np.float32))
        b = mn.meshFromFacesVerts(fb.astype(np.int32), vb.astype(np.float32))
        return float(np.sqrt(mr.findMaxDistanceSq(mr.MeshPart(a), mr.MeshPart(b))))

    seconds, value = fastest(args.reps, work)
    return {"value": value, "samples": "vertices", "seconds": seconds}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("inputs", nargs="+")
    parser.add_argument("--engine", required=True, choices=["proxima", "pymeshlab", "trimesh", "meshlib"])
    parser.add_argument("--tolerance", type=float, default=1e-4, help="fraction of the larger diagonal")
    parser.add_argument("--samples", type=int, default=100_000)
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--export")
    args = parser.parse_args()
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    result = globals()[f"run_{args.engine}"](args)
    print(json.dumps({"engine": args.engine, **result}))


if __name__ == "__main__":
    main()

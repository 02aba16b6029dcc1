#!/usr/bin/env python3
"""Texture lookup for an image of rays (issue 38): the texture coordinates
seen by every pixel of an N x N camera looking at the spot cow, with
proxima, Open3D's RaycastingScene and trimesh, one thread each, in one
process.

    uv_bench.py [--mesh FILE] [--size N] [--loop-pixels K] [--reps R] [--out FILE]

Each row times the whole lookup from the rays to the (N*N, 2) texture
coordinates, with the structures built first:

- proxima: ``mesh.cast_rays(origins, directions, return_uv=True, threads=1)``;
- Open3D: ``RaycastingScene.cast_rays(rays, nthreads=1)``, then its
  ``primitive_uvs`` (barycentric u, v) combined with the mesh's
  ``triangle_uvs`` in numpy;
- trimesh, vectorized: ``ray.intersects_location`` (Embree through embreex
  when it imports, else trimesh's own), ``points_to_barycentric``, and the
  UVs of the hit faces, in numpy;
- trimesh, per pixel (the loop of trimesh issue #1733): the same calls one
  ray at a time, on the first K pixels, reported per pixel and scaled to the
  image.

The answers are compared where both proxima and the peer hit: the share of
pixels whose UVs agree within 1e-4. Output JSON: the seconds per row and
proxima's speed-up over each peer.
"""

import argparse
from pathlib import Path

import numpy as np

import proxima
from _timing import report, timed

SPOT = Path(__file__).resolve().parents[4] / "shared" / "data" / "spot_triangulated.obj"


def camera_rays(lo, hi, size):
    """An N x N pinhole camera two diagonals in front of the box, looking at its centre."""
    centre = (lo + hi) / 2
    diagonal = np.linalg.norm(hi - lo)
    eye = centre + np.array([0.3, 0.2, 1.0]) / np.linalg.norm([0.3, 0.2, 1.0]) * 2 * diagonal
    forward = (centre - eye) / np.linalg.norm(centre - eye)
    right = np.cross(forward, [0, 1, 0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    s = (np.arange(size) + 0.5) / size * 2 - 1
    x, y = np.meshgrid(s, s)
    half = np.tan(np.radians(15))
    directions = forward + half * (x.reshape(-1, 1) * right + y.reshape(-1, 1) * up)
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    origins = np.broadcast_to(eye, directions.shape).copy()
    return origins.astype(np.float32), directions.astype(np.float32)


def agreement(ours, theirs):
    both = ~np.isnan(ours[:, 0]) & ~np.isnan(theirs[:, 0])
    if not both.any():
        return 0.0
    return float(np.mean(np.abs(ours[both] - theirs[both]).max(axis=1) < 1e-4))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--mesh", default=str(SPOT))
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--loop-pixels", type=int, default=2000)
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--out")
    args = parser.parse_args()

    mesh = proxima.load(args.mesh)
    lo, hi = mesh.bounds
    origins, directions = camera_rays(lo, hi, args.size)
    mesh.cast_rays(origins[:10], directions[:10], return_uv=True)  # builds the ray tree
    seconds, ratios, agree = {}, {}, {}

    def ours():
        return mesh.cast_rays(origins, directions, threads=1, return_uv=True).uv

    seconds["proxima"], uv = timed(args.reps, ours)
    hits = int(np.sum(~np.isnan(uv[:, 0])))

    try:
        import open3d as o3d

        legacy = o3d.io.read_triangle_mesh(args.mesh)
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(legacy))
        triangle_uvs = np.asarray(legacy.triangle_uvs).reshape(-1, 3, 2)
        rays = o3d.core.Tensor(np.hstack([origins, directions]), dtype=o3d.core.Dtype.Float32)

        def open3d():
            answer = scene.cast_rays(rays, nthreads=1)
            face = answer["primitive_ids"].numpy().astype(np.int64)
            bary = answer["primitive_uvs"].numpy().astype(np.float64)
            hit = face != o3d.t.geometry.RaycastingScene.INVALID_ID
            out = np.full((len(face), 2), np.nan)
            w = np.stack([1 - bary[hit, 0] - bary[hit, 1], bary[hit, 0], bary[hit, 1]], axis=1)
            out[hit] = np.einsum("nk,nkd->nd", w, triangle_uvs[face[hit]])
            return out

        open3d()
        seconds["open3d"], theirs = timed(args.reps, open3d)
        agree["open3d"] = agreement(uv, theirs)
    except ImportError:
        pass

    import trimesh

    tm = trimesh.load(args.mesh, process=False)
    tm_uv = np.asarray(tm.visual.uv, dtype=np.float64)

    def lookup(o, d):
        locations, ray, face = tm.ray.intersects_location(o, d, multiple_hits=False)
        out = np.full((len(o), 2), np.nan)
        bary = trimesh.triangles.points_to_barycentric(tm.triangles[face], locations)
        out[ray] = np.einsum("nk,nkd->nd", bary, tm_uv[tm.faces[face]])
        return out

    lookup(origins[:10], directions[:10])  # builds its intersector
    seconds["trimesh"], theirs = timed(1, lambda: lookup(origins, directions))
    agree["trimesh"] = agreement(uv, theirs)
    k = min(args.loop_pixels, len(origins))
    loop, _ = timed(1, lambda: [lookup(origins[i : i + 1], directions[i : i + 1]) for i in range(k)])
    seconds["trimesh per pixel (scaled)"] = loop / k * len(origins)

    for peer in seconds:
        if peer != "proxima":
            ratios[peer] = seconds[peer] / seconds["proxima"]
    values = {
        "mesh": args.mesh,
        "image": [args.size, args.size],
        "hits": hits,
        "trimesh_intersector": type(tm.ray).__module__,
        "seconds": seconds,
        "proxima_speedup": ratios,
        "uv_agreement": agree,
    }
    report(values, args.out)


if __name__ == "__main__":
    main()

"""A deforming mesh, frame by frame (issue 37's per-frame loop): each frame
moves every vertex of the mesh (a travelling wave of 1% of the diagonal),
then asks 100k closest points near the surface and casts 100k rays, one
core. proxima refits its structures (``Mesh.update_vertices``); Embree
(embreex) and Open3D's ``RaycastingScene`` expose no refit, so their scenes
are built anew each frame, as their users do. Embree answers rays only; its
row is rays alone, against proxima's rays alone.

    OMP_NUM_THREADS=1 RAYON_NUM_THREADS=1 taskset -c 0 \\
        python refit_bench.py MESH [--frames 10] [--queries 100000] [--out F]

Needs numpy, proxima, open3d-cpu and embreex (the peers' environment of
crates/proxima-bench/peers). Prints seconds per frame and the ratios, as
JSON."""

import argparse
import time

import numpy as np

import proxima
from _timing import report


def frames(vertices, count):
    """The vertex arrays of `count` frames of the wave."""
    lo, hi = vertices.min(0), vertices.max(0)
    diagonal = float(np.linalg.norm(hi - lo))
    x = (vertices[:, 0] - lo[0]) / diagonal
    for k in range(count):
        moved = vertices.copy()
        moved[:, 1] += 0.01 * diagonal * np.sin(8 * x + 0.7 * k)
        yield moved.astype(np.float32)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("mesh")
    parser.add_argument("--frames", type=int, default=10)
    parser.add_argument("--queries", type=int, default=100_000)
    parser.add_argument("--out")
    args = parser.parse_args()
    mesh = proxima.load(args.mesh)
    vertices = np.asarray(mesh.vertices, dtype=np.float32)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    rng = np.random.default_rng(1)
    lo, hi = vertices.min(0), vertices.max(0)
    diagonal = float(np.linalg.norm(hi - lo))
    picked = faces[rng.integers(0, len(faces), args.queries)]
    points = (vertices[picked].mean(1) + rng.normal(0, 0.01 * diagonal, (args.queries, 3))).astype(np.float32)
    centre = (lo + hi) / 2
    direction = rng.normal(size=(args.queries, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    origins = (centre + 0.75 * diagonal * direction).astype(np.float32)
    targets = rng.uniform(lo, hi, (args.queries, 3))
    directions = (targets - origins).astype(np.float32)
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    steps = list(frames(vertices, args.frames))

    def run(step):
        start = time.perf_counter()
        for moved in steps:
            step(moved)
        return (time.perf_counter() - start) / len(steps)

    moving = proxima.Mesh(vertices, faces)
    moving.closest_points(points[:10])
    moving.cast_rays(origins[:10], directions[:10])

    def proxima_frame(moved, closest=True):
        moving.update_vertices(moved)
        if closest:
            moving.closest_points(points)
        moving.cast_rays(origins, directions)

    def proxima_rebuild(moved):
        fresh = proxima.Mesh(moved, faces)
        fresh.closest_points(points)
        fresh.cast_rays(origins, directions)

    import open3d as o3d

    o3d_rays = o3d.core.Tensor(np.hstack([origins, directions]))
    o3d_points = o3d.core.Tensor(points)
    o3d_faces = o3d.core.Tensor(faces.astype(np.uint32))

    def open3d_frame(moved):
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(o3d.core.Tensor(moved), o3d_faces)
        scene.compute_closest_points(o3d_points)
        scene.cast_rays(o3d_rays)

    from embreex import rtcore_scene, mesh_construction

    def embree_frame(moved):
        scene = rtcore_scene.EmbreeScene()
        mesh_construction.TriangleMesh(scene, moved[faces])
        scene.run(origins, directions, output=1)

    results = {}
    for name, step in [
        ("proxima refit", proxima_frame),
        ("proxima rebuilt", proxima_rebuild),
        ("open3d rebuilt", open3d_frame),
        ("proxima refit, rays only", lambda m: proxima_frame(m, closest=False)),
        ("embree rebuilt, rays only", embree_frame),
    ]:
        results[name] = run(step)
    results["open3d / proxima"] = results["open3d rebuilt"] / results["proxima refit"]
    results["embree / proxima (rays)"] = results["embree rebuilt, rays only"] / results["proxima refit, rays only"]
    results["rebuilt / refit (proxima)"] = results["proxima rebuilt"] / results["proxima refit"]
    report({"mesh": args.mesh, "triangles": int(len(faces)), "frames": args.frames, **results}, args.out)


if __name__ == "__main__":
    main()

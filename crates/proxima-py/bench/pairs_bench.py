#!/usr/bin/env python3
"""Two meshes under rigid motion (issue 36): the Python peers on the poses of
a workload folder written by proxima-bench's `pairs poses`.

    pairs_bench.py DIR [--distance-poses N] [--collide-poses N] [--out FILE]
    pairs_bench.py --self MESH.ply [--out FILE]

DIR holds a.ply and b.ply (binary PLY: the exact float32 coordinates proxima
reads) and {near,far,overlap}.poses (16 numbers per line, the row-major 4x4
pose of b; a stays unmoved). Per pose, on one thread (the process is pinned
to one CPU):

- coal: `coal.distance` and `coal.collide` between two BVHModelOBBRSS;
- MeshLib: `findDistance` and `findCollidingTriangles(firstIntersectionOnly)`;
- trimesh's CollisionManager (python-fcl), when it imports:
  `min_distance_single` and `in_collision_single`.

Every peer gets the same float32 vertices (as float64 where it takes
float64) and the same poses. Structures are built before timing. Each
method runs on the first N poses of each class (its own N: the slow ones on
fewer), one after another in pose order, after one untimed warm-up pose.

`--self MESH.ply`: MeshLib's `findSelfCollidingTriangles` (touching counts,
as in proxima), timed, and the face pairs written for `pairs judge-self`.

Output JSON: per peer and class, the pose indices, answers (distance,
triangles, witness points, collision) and seconds; `pairs judge DIR FILE`
(proxima-bench) judges every answer against proxima's.
"""

import argparse
import json
import os
import sys
import time

import numpy as np


def read_ply(path):
    """The vertices (float32, N x 3) and triangles (int32, M x 3) of a binary
    little-endian PLY as proxima-bench writes it."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().split("\n")
    nv = next(int(l.split()[2]) for l in header if l.startswith("element vertex"))
    nf = next(int(l.split()[2]) for l in header if l.startswith("element face"))
    vertices = np.frombuffer(data, dtype="<f4", count=3 * nv, offset=end).reshape(nv, 3)
    faces = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)]), count=nf, offset=end + 12 * nv)
    if not (faces["n"] == 3).all():
        sys.exit(f"{path}: faces that are not triangles")
    return vertices.copy(), faces["i"].copy()


def read_poses(path):
    poses = np.loadtxt(path, comments="#", ndmin=2)
    if poses.shape[1] != 16:
        sys.exit(f"{path}: {poses.shape[1]} numbers per line, not 16")
    return poses.reshape(-1, 4, 4)


def pin_one_cpu():
    """Pins the process (every thread it will start) to one CPU."""
    cpu = sorted(os.sched_getaffinity(0))[0]
    os.sched_setaffinity(0, {cpu})
    return cpu


def timed_loop(count, one):
    """`one(i)` for i in 0..count after one untimed warm-up; answers and seconds."""
    if count == 0:
        return [], 0.0
    one(0)
    start = time.perf_counter()
    answers = [one(i) for i in range(count)]
    return answers, time.perf_counter() - start


def columns(answers, count):
    out = {"pose": list(range(count))}
    for key in ("distance", "triangle_a", "triangle_b", "point_a", "point_b", "intersects"):
        values = [a.get(key) for a in answers]
        if any(v is not None for v in values):
            out[key] = values
    return out


def coal_peer(va, fa, vb, fb, classes, n_distance, n_collide):
    import coal

    def model(v, f):
        m = coal.BVHModelOBBRSS()
        m.beginModel(len(f), len(v))
        m.addVertices(np.ascontiguousarray(v, dtype=np.float64))
        m.addTriangles(np.ascontiguousarray(f, dtype=np.int64))
        m.endModel()
        return m

    start = time.perf_counter()
    ma, mb = model(va, fa), model(vb, fb)
    build = time.perf_counter() - start
    identity = coal.Transform3s()
    result = {"peer": "coal", "version": getattr(coal, "__version__", "?"), "build_seconds": build, "classes": {}}
    for name, poses in classes.items():
        transforms = [coal.Transform3s(np.ascontiguousarray(p[:3, :3]), np.ascontiguousarray(p[:3, 3])) for p in poses]

        def distance(i):
            req, res = coal.DistanceRequest(), coal.DistanceResult()
            d = coal.distance(ma, identity, mb, transforms[i], req, res)
            return {
                "distance": max(float(d), 0.0),
                "raw_distance": float(d),
                "triangle_a": int(res.b1),
                "triangle_b": int(res.b2),
                "point_a": [float(x) for x in res.getNearestPoint1()],
                "point_b": [float(x) for x in res.getNearestPoint2()],
            }

        def collide(i):
            req, res = coal.CollisionRequest(), coal.CollisionResult()
            coal.collide(ma, identity, mb, transforms[i], req, res)
            return {"intersects": bool(res.isCollision())}

        nd, nc = min(n_distance, len(poses)), min(n_collide, len(poses))
        dist, s_dist = timed_loop(nd, distance)
        coll, s_coll = timed_loop(nc, collide)
        answers = [dict(dist[i] if i < nd else {}, **(coll[i] if i < nc else {})) for i in range(max(nd, nc))]
        cols = columns(answers, max(nd, nc))
        cols["negative_distances"] = sum(1 for a in dist if a["raw_distance"] < 0)
        cols["timing"] = {"distance": {"poses": nd, "seconds": s_dist}, "intersects": {"poses": nc, "seconds": s_coll}}
        result["classes"][name] = cols
    return result


def meshlib_mesh(v, f):
    import meshlib.mrmeshnumpy as mn

    return mn.meshFromFacesVerts(np.ascontiguousarray(f, dtype=np.int32), np.ascontiguousarray(v, dtype=np.float32))


def meshlib_xf(pose):
    import meshlib.mrmeshpy as mr

    r = pose[:3, :3].astype(np.float32)
    t = pose[:3, 3].astype(np.float32)
    m = mr.Matrix3f(mr.Vector3f(*map(float, r[0])), mr.Vector3f(*map(float, r[1])), mr.Vector3f(*map(float, r[2])))
    return mr.AffineXf3f(m, mr.Vector3f(*map(float, t)))


def meshlib_peer(va, fa, vb, fb, classes, n_distance, n_collide):
    import meshlib.mrmeshpy as mr

    start = time.perf_counter()
    ma, mb = meshlib_mesh(va, fa), meshlib_mesh(vb, fb)
    pa, pb = mr.MeshPart(ma), mr.MeshPart(mb)
    # The trees are built on first use: build them here, untimed.
    ma.getAABBTree()
    mb.getAABBTree()
    build = time.perf_counter() - start
    faces = [ma.topology.numValidFaces(), mb.topology.numValidFaces()]
    result = {"peer": "meshlib", "build_seconds": build, "valid_faces": faces, "triangles": [len(fa), len(fb)], "classes": {}}
    for name, poses in classes.items():
        xfs = [meshlib_xf(p) for p in poses]

        def distance(i):
            r = mr.findDistance(pa, pb, xfs[i])
            pose = poses[i]
            # MeshLib's b point is in b's own frame: place it as proxima does.
            b_local = np.array([r.b.point.x, r.b.point.y, r.b.point.z], dtype=np.float64)
            return {
                "distance": float(np.sqrt(max(r.distSq, 0.0))),
                "triangle_a": int(r.a.face.get()),
                "triangle_b": int(r.b.face.get()),
                "point_a": [float(r.a.point.x), float(r.a.point.y), float(r.a.point.z)],
                "point_b": [float(x) for x in pose[:3, :3] @ b_local + pose[:3, 3]],
            }

        def collide(i):
            return {"intersects": len(mr.findCollidingTriangles(pa, pb, xfs[i], True)) > 0}

        nd, nc = min(n_distance, len(poses)), min(n_collide, len(poses))
        dist, s_dist = timed_loop(nd, distance)
        coll, s_coll = timed_loop(nc, collide)
        answers = [dict(dist[i] if i < nd else {}, **(coll[i] if i < nc else {})) for i in range(max(nd, nc))]
        cols = columns(answers, max(nd, nc))
        cols["timing"] = {"distance": {"poses": nd, "seconds": s_dist}, "intersects": {"poses": nc, "seconds": s_coll}}
        result["classes"][name] = cols
    return result


def trimesh_peer(va, fa, vb, fb, classes, n_distance, n_collide):
    import trimesh
    from trimesh.collision import CollisionManager

    start = time.perf_counter()
    manager = CollisionManager()
    manager.add_object("a", trimesh.Trimesh(va.astype(np.float64), fa, process=False))
    other = trimesh.Trimesh(vb.astype(np.float64), fb, process=False)
    # The BVH of b is made once; each pose moves its transform only.
    probe = CollisionManager()
    probe.add_object("b", other)
    build = time.perf_counter() - start
    result = {"peer": "trimesh-fcl", "build_seconds": build, "classes": {}}
    for name, poses in classes.items():

        def distance(i):
            probe.set_transform("b", poses[i])
            return {"distance": float(manager.min_distance_other(probe))}

        def collide(i):
            probe.set_transform("b", poses[i])
            return {"intersects": bool(manager.in_collision_other(probe))}

        nd, nc = min(n_distance, len(poses)), min(n_collide, len(poses))
        dist, s_dist = timed_loop(nd, distance)
        coll, s_coll = timed_loop(nc, collide)
        answers = [dict(dist[i] if i < nd else {}, **(coll[i] if i < nc else {})) for i in range(max(nd, nc))]
        cols = columns(answers, max(nd, nc))
        cols["timing"] = {"distance": {"poses": nd, "seconds": s_dist}, "intersects": {"poses": nc, "seconds": s_coll}}
        result["classes"][name] = cols
    return result


def self_intersections(path, reps):
    import meshlib.mrmeshpy as mr

    v, f = read_ply(path)
    mesh = meshlib_mesh(v, f)
    part = mr.MeshPart(mesh)
    mesh.getAABBTree()
    seconds = []
    pairs = []
    for _ in range(reps):
        start = time.perf_counter()
        found = mr.findSelfCollidingTriangles(part, touchIsIntersection=True)
        seconds.append(time.perf_counter() - start)
        pairs = [[int(p.aFace.get()), int(p.bFace.get())] for p in found]
    return {"peer": "meshlib", "mesh": path, "triangles": len(f), "valid_faces": mesh.topology.numValidFaces(),
            "pairs": pairs, "count": len(pairs), "seconds": seconds}


PEERS = {"coal": coal_peer, "meshlib": meshlib_peer, "trimesh": trimesh_peer}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dir", nargs="?", help="workload folder (a.ply, b.ply, *.poses)")
    parser.add_argument("--peers", default="coal,meshlib,trimesh", help="comma-separated: coal, meshlib, trimesh")
    parser.add_argument("--classes", default="near,far,overlap")
    parser.add_argument("--distance-poses", type=int, default=200, help="distance on the first N poses per class")
    parser.add_argument("--collide-poses", type=int, default=1000, help="collision on the first N poses per class")
    parser.add_argument("--slow-poses", type=int, default=20, help="trimesh's CollisionManager on the first N poses")
    parser.add_argument("--self", dest="self_mesh", help="MeshLib self-intersections of this PLY instead")
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--all-cpus", action="store_true", help="do not pin to one CPU")
    parser.add_argument("--out", help="JSON output (default: stdout)")
    args = parser.parse_args()
    cpu = None if args.all_cpus else pin_one_cpu()
    load = os.getloadavg()
    if args.self_mesh:
        out = self_intersections(args.self_mesh, args.reps)
    else:
        if not args.dir:
            parser.error("a workload folder or --self MESH")
        va, fa = read_ply(os.path.join(args.dir, "a.ply"))
        vb, fb = read_ply(os.path.join(args.dir, "b.ply"))
        classes = {c: read_poses(os.path.join(args.dir, f"{c}.poses")) for c in args.classes.split(",")}
        out = {"dir": args.dir, "peers": []}
        for name in args.peers.split(","):
            slow = name == "trimesh"
            nd = min(args.distance_poses, args.slow_poses) if slow else args.distance_poses
            nc = min(args.collide_poses, args.slow_poses) if slow else args.collide_poses
            try:
                out["peers"].append(PEERS[name](va, fa, vb, fb, classes, nd, nc))
            except ImportError as e:
                print(f"note: {name} does not import ({e}); skipped", file=sys.stderr)
    out["cpu"] = cpu
    out["load_average"] = [load, os.getloadavg()]
    text = json.dumps(out)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    else:
        print(text)


if __name__ == "__main__":
    main()

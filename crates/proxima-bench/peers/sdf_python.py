"""proxima's Python `Mesh.signed_distance` against Open3D's
`compute_signed_distance`, one thread each, on the query sets that
`sdf_compare --export DIR` wrote (run-sdf-peers.sh leaves them in
target/sdf-peers); best of 5 calls, and the points whose signs differ.

    PYTHON sdf_python.py EXPORT_DIR PEERS_SITE_PACKAGES NAME [NAME ...]

PYTHON is a venv with proxima installed (scripts/test makes target/py-venv);
PEERS_SITE_PACKAGES the site-packages of run-sdf-peers.sh's venv (Open3D),
appended to the path after proxima's own. Pin it to one core (taskset -c 0).
"""
import os
import sys
import time

export, peers = sys.argv[1], sys.argv[2]
sys.path.append(peers)
import numpy as np  # noqa: E402
import open3d as o3d  # noqa: E402
import proxima  # noqa: E402


def best(call, reps=5):
    fastest = float("inf")
    for _ in range(reps):
        start = time.perf_counter()
        call()
        fastest = min(fastest, time.perf_counter() - start)
    return fastest


print("| mesh | set | proxima sd/s | Open3D sd/s | proxima / Open3D | signs differ |")
print("|---|---|---|---|---|---|")
for name in sys.argv[3:]:
    folder = os.path.join(export, name)
    legacy = o3d.io.read_triangle_mesh(os.path.join(folder, "mesh.ply"))
    mesh = proxima.Mesh(np.asarray(legacy.vertices, np.float32), np.asarray(legacy.triangles, np.uint32))
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(legacy))
    for which in ["near", "uniform"]:
        points = np.load(os.path.join(folder, f"{which}.npy")).astype(np.float32)
        tensor = o3d.core.Tensor(points)
        # Both build their structures on the first call, untimed.
        mesh.signed_distance(points[:10], threads=1)
        scene.compute_signed_distance(o3d.core.Tensor(points[:10]), nthreads=1)
        ours = best(lambda: mesh.signed_distance(points, threads=1))
        theirs = best(lambda: scene.compute_signed_distance(tensor, nthreads=1).numpy())
        a = mesh.signed_distance(points, threads=1)
        b = scene.compute_signed_distance(tensor, nthreads=1).numpy()
        differ = int(np.sum((a < 0) != (b < 0)))
        n = len(points)
        print(f"| {name} | {which} | {n / ours:,.0f} | {n / theirs:,.0f} | {theirs / ours:.2f}x | {differ} of {n} |", flush=True)

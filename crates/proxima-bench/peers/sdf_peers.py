#!/usr/bin/env python3
"""Open3D and libigl signed distances on the query sets that `sdf_compare --export DIR` wrote.

    python sdf_peers.py DIR [MESH ...] [--libigl-queries N] [--rounds N] [--oracle-cap N]

For each mesh folder in DIR (mesh.ply, SET.npy, SET_sd.npy, SET_w.npy, SET_pn_sd.npy,
SET_exact_w.npy, timings.json; see crates/proxima-bench/src/bin/sdf_compare.rs) and each
query set (near, uniform):

- times, one thread, best of --rounds: Open3D `RaycastingScene.compute_signed_distance(points,
  nthreads=1)` (sign by the parity of one ray) and `compute_distance` (unsigned, for scale);
  libigl `signed_distance(P, V, F, sign_type=SIGNED_DISTANCE_TYPE_FAST_WINDING_NUMBER)`, whose
  every call builds its trees: it is timed (best of 2) on the first --libigl-queries points and
  on one point, and both the rate per call and the rate net of the one-point call (the build) are
  printed;
- prints proxima's rates (timings.json, measured by the Rust binary in the same run) and the
  ratios proxima / peer;
- compares signs (inside = negative distance): proxima (winding-number sign) against Open3D
  and against libigl on every point timed, and against its own pseudonormal sign; where they differ, an exact winding number
  computed here in float64 numpy (sum of Van Oosterom-Strackee solid angles over every
  triangle, independent of proxima's) says who is right, on up to --oracle-cap points per
  set; and on the points with proxima's exported exact winding number (SET_exact_w.npy),
  each method's wrong signs where |w - 1/2| > 0.01.

Run it pinned to one core (run-sdf-peers.sh does: taskset -c 0, OMP_NUM_THREADS=1,
IGL_NUM_THREADS=1).
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

SETS = ("near", "uniform")


def read_ply(path):
    """The binary little-endian PLY that sdf_compare writes: float x y z, triangles."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    if header[1] != "format binary_little_endian 1.0":
        raise ValueError(f"{path}: not the binary PLY that sdf_compare writes")
    counts = {line.split()[1]: int(line.split()[2]) for line in header if line.startswith("element")}
    nv, nf = counts["vertex"], counts["face"]
    # Copied: the header's length leaves the data unaligned, which Open3D refuses.
    vertices = np.frombuffer(data, dtype="<f4", count=3 * nv, offset=end).reshape(nv, 3).astype(np.float32)
    faces = np.frombuffer(data, dtype=[("n", "u1"), ("i", "<i4", (3,))], count=nf, offset=end + 12 * nv)
    if not np.all(faces["n"] == 3):
        raise ValueError(f"{path}: a face is not a triangle")
    return vertices, faces["i"].astype(np.int64)


def best_time(function, rounds):
    """Best of `rounds` timed calls after an untimed one; returns (value, seconds)."""
    value = function()
    best = math.inf
    for _ in range(rounds):
        start = time.perf_counter()
        value = function()
        best = min(best, time.perf_counter() - start)
    return value, best


class ExactWinding:
    """Generalized winding numbers summed over every triangle in float64 (the oracle)."""

    def __init__(self, vertices, triangles):
        v = vertices.astype(np.float64)
        self.a, self.b, self.c = v[triangles[:, 0]], v[triangles[:, 1]], v[triangles[:, 2]]
        # By the point's coordinates: a point both peers dispute is summed once.
        self.known = {}

    def __call__(self, p):
        key = tuple(p)
        if key not in self.known:
            self.known[key] = self.sum(np.asarray(p, dtype=np.float64))
        return self.known[key]

    def sum(self, p):
        a, b, c = self.a - p, self.b - p, self.c - p
        la, lb, lc = (np.sqrt(np.einsum("ij,ij->i", x, x)) for x in (a, b, c))
        det = np.einsum("ij,ij->i", a, np.cross(b, c))
        dot = lambda x, y: np.einsum("ij,ij->i", x, y)  # noqa: E731
        denominator = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb
        return float(np.sum(2.0 * np.arctan2(det, denominator)) / (4.0 * math.pi))


def judge(name, ours, theirs, points, oracle, cap, rng):
    """Sign differences between proxima and a peer, and who is right where they differ."""
    differ = np.flatnonzero(ours != theirs)
    checked = differ if len(differ) <= cap else np.sort(rng.choice(differ, cap, replace=False))
    right = {"proxima": 0, name: 0, "unclear": 0}
    for k in checked:
        w = oracle(points[k].astype(np.float64))
        if abs(w - 0.5) <= 0.01:
            right["unclear"] += 1
        elif (w > 0.5) == ours[k]:
            right["proxima"] += 1
        else:
            right[name] += 1
    return len(differ), len(checked), right


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dir")
    parser.add_argument("meshes", nargs="*", help="mesh folders in DIR (default: all)")
    parser.add_argument("--libigl-queries", type=int, default=20000)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--oracle-cap", type=int, default=50)
    args = parser.parse_args()

    import igl
    import open3d as o3d

    igl_version = getattr(igl, "__version__", None)
    if igl_version is None:
        from importlib.metadata import version

        igl_version = version("libigl")
    print(f"load average {open('/proc/loadavg').read().split()[:3]}; "
          f"numpy {np.__version__}, open3d {o3d.__version__}, libigl {igl_version}; "
          f"one thread, best of {args.rounds} rounds; affinity {sorted(os.sched_getaffinity(0))}")
    meshes = args.meshes or sorted(
        d for d in os.listdir(args.dir) if os.path.isfile(os.path.join(args.dir, d, "timings.json"))
    )
    rng = np.random.default_rng(1)
    speed_rows, sign_rows, oracle_rows = [], [], []
    for mesh in meshes:
        folder = os.path.join(args.dir, mesh)
        with open(os.path.join(folder, "timings.json")) as f:
            proxima = json.load(f)
        vertices, triangles = read_ply(os.path.join(folder, "mesh.ply"))
        print(f"\n## {mesh}: {len(triangles)} triangles, {len(vertices)} vertices")
        start = time.perf_counter()
        scene = o3d.t.geometry.RaycastingScene(nthreads=1) if _takes_nthreads() else o3d.t.geometry.RaycastingScene()
        scene.add_triangles(o3d.core.Tensor(vertices), o3d.core.Tensor(triangles.astype(np.uint32)))
        # Embree builds its tree on the first query.
        scene.compute_distance(o3d.core.Tensor(np.zeros((1, 3), np.float32)), nthreads=1)
        print(f"Open3D scene and tree: {time.perf_counter() - start:.2f} s")
        v64 = vertices.astype(np.float64)
        fwn = igl.SIGNED_DISTANCE_TYPE_FAST_WINDING_NUMBER
        oracle = ExactWinding(vertices, triangles)
        for set_name in SETS:
            points = np.load(os.path.join(folder, f"{set_name}.npy"))
            n = len(points)
            ours_sd = np.load(os.path.join(folder, f"{set_name}_sd.npy"))
            ours_pn = np.load(os.path.join(folder, f"{set_name}_pn_sd.npy"))
            exact = np.load(os.path.join(folder, f"{set_name}_exact_w.npy"))
            tensor = o3d.core.Tensor(points)
            o3d_sd, t_o3d = best_time(lambda: scene.compute_signed_distance(tensor, nthreads=1).numpy(), args.rounds)
            _, t_o3d_unsigned = best_time(lambda: scene.compute_distance(tensor, nthreads=1).numpy(), args.rounds)
            m = min(args.libigl_queries, n)
            subset = points[:m].astype(np.float64)
            # Every call builds libigl's trees (the closest-point tree and the
            # winding numbers' expansions): time it alone on one point.
            igl_sd, t_igl = best_time(lambda: igl.signed_distance(subset, v64, triangles, sign_type=fwn)[0], 2)
            _, t_igl_build = best_time(lambda: igl.signed_distance(subset[:1], v64, triangles, sign_type=fwn)[0], 2)
            rates = proxima["sets"][set_name]
            r_ours, r_batch = rates["sd_winding"], rates["sd_winding_batch"]
            r_o3d, r_igl = n / t_o3d, m / t_igl
            r_igl_net = m / max(t_igl - t_igl_build, 1e-9)
            speed_rows.append(
                f"| {mesh} | {set_name} | {r_ours:.0f} | {r_batch:.0f} | {rates['sd_pseudonormal']:.0f} | "
                f"{rates['closest']:.0f} | {r_o3d:.0f} | {n / t_o3d_unsigned:.0f} | {r_igl:.0f} ({m}) | "
                f"{r_igl_net:.0f} | {r_ours / r_o3d:.2f}x | {r_batch / r_o3d:.2f}x | {r_ours / r_igl:.1f}x | "
                f"{r_ours / r_igl_net:.1f}x | {rates['closest'] / rates['sd_pseudonormal']:.2f}x |"
            )
            # Signs: True = inside. A point at distance 0 counts as outside.
            ours_in, pn_in = ours_sd < 0, ours_pn < 0
            o3d_in, igl_in = o3d_sd < 0, igl_sd < 0
            d_o3d, c_o3d, right_o3d = judge("Open3D", ours_in, o3d_in, points, oracle, args.oracle_cap, rng)
            d_igl, c_igl, right_igl = judge("libigl", ours_in[:m], igl_in, points, oracle, args.oracle_cap, rng)
            d_pn, c_pn, right_pn = judge("pseudonormal", ours_in, pn_in, points, oracle, args.oracle_cap, rng)
            sign_rows.append(
                f"| {mesh} | {set_name} | {d_o3d} of {n} | {c_o3d}: {right_o3d['proxima']} / {right_o3d['Open3D']} / "
                f"{right_o3d['unclear']} | {d_igl} of {m} | {c_igl}: {right_igl['proxima']} / "
                f"{right_igl['libigl']} / {right_igl['unclear']} | {d_pn} of {n} | {c_pn}: {right_pn['proxima']} / "
                f"{right_pn['pseudonormal']} / {right_pn['unclear']} |"
            )
            k = len(exact)
            clear = np.abs(exact - 0.5) > 0.01
            inside = exact > 0.5
            def wrong(signs):
                j = min(k, len(signs))
                return int(np.sum((signs[:j] != inside[:j]) & clear[:j]))

            # The exported exact values against this script's own oracle, on a few points.
            few = range(min(k, 5))
            agree = max((abs(oracle(points[i].astype(np.float64)) - exact[i]) for i in few), default=0.0)
            oracle_rows.append(
                f"| {mesh} | {set_name} | {k} ({int(np.sum(clear))} clear) | {wrong(ours_in)} | {wrong(pn_in)} | "
                f"{wrong(o3d_in)} | {wrong(igl_in)} (of {min(k, m)}) | {agree:.1e} |"
            )
            print(f"{set_name}: done ({time.perf_counter() - start:.0f} s since the mesh was read)")
    print(f"load average at the end {open('/proc/loadavg').read().split()[:3]}")
    print("\n### Queries per second, one core (proxima columns from sdf_compare in the same run)")
    print("| mesh | set | proxima sd | proxima sd batch | proxima pseudonormal sd | proxima closest | Open3D sd | "
          "Open3D unsigned | libigl sd per call (queries) | libigl sd net of build | proxima/Open3D | "
          "proxima batch/Open3D | proxima/libigl per call | proxima/libigl net | pseudonormal/closest time |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(speed_rows))
    print("\n### Signs: proxima (winding number) against the peers; where they differ, checked against an exact "
          "winding number (numpy, float64): proxima right / peer right / |w - 1/2| <= 0.01")
    print("| mesh | set | differ from Open3D | checked: proxima / Open3D / unclear | differ from libigl | "
          "checked: proxima / libigl / unclear | proxima pseudonormal sign differs | "
          "checked: winding / pseudonormal / unclear |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(sign_rows))
    print("\n### Wrong signs on the points with proxima's exported exact winding number (|w - 1/2| > 0.01)")
    print("| mesh | set | points | proxima winding | proxima pseudonormal | Open3D | libigl | "
          "max diff, exported exact vs numpy (5 points) |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(oracle_rows))


def _takes_nthreads():
    """Whether this Open3D's RaycastingScene constructor takes nthreads (0.18 on)."""
    import open3d as o3d

    return "nthreads" in (o3d.t.geometry.RaycastingScene.__init__.__doc__ or "")


if __name__ == "__main__":
    sys.exit(main())

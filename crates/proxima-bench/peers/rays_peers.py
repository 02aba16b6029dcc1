"""First-hit rays: proxima against Embree (embreex), Open3D, parry3d and obvhs, one core, one run.

    rays_peers.py PROXIMA_BINARY MESH.ply [MESH.ply ...] [--rays N] [--rounds R]

For each mesh: the `rays` set of ../shared/BENCHMARKS.md (origins on a sphere
of radius 0.75 x the bounding-box diagonal around the box centre, aimed at
uniform points of the box; seeded), directions normalized. proxima casts them
with `proxima raycast MESH --rays FILE --json --threads 1` (its `seconds`
time the casting alone, after its build); Embree through embreex
(`EmbreeScene.run`, which uses the threads it is given: run this script
pinned to one core); Open3D with `RaycastingScene.cast_rays(nthreads=1)`; parry3d and obvhs
(its CWBVH, medium_build preset) through the `rays_peers` binary beside
PROXIMA_BINARY (target/release/rays_peers, from crates/proxima-bench), which
reads the same mesh and rays file and prints one JSON line per peer with its
build and cast times and its t per ray (null for a miss).
Best of R rounds each. Then the answers are compared: hit or miss, and t
within 1e-4 relative where both hit.
"""
import json, subprocess, sys, tempfile, time, os
import numpy as np

def rays_set(vertices, n, seed=1):
    lo, hi = vertices.min(0), vertices.max(0)
    centre, diag = (lo + hi) / 2, np.linalg.norm(hi - lo)
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(n, 3)); u /= np.linalg.norm(u, axis=1)[:, None]
    origins = centre + u * 0.75 * diag
    targets = rng.uniform(lo, hi, size=(n, 3))
    d = targets - origins
    d /= np.linalg.norm(d, axis=1)[:, None]
    return origins.astype(np.float32), d.astype(np.float32)

def best(rounds, f):
    times, out = [], None
    for _ in range(rounds):
        t = time.perf_counter(); out = f(); times.append(time.perf_counter() - t)
    return min(times), out

def main():
    args = sys.argv[1:]
    n = int(args[args.index("--rays") + 1]) if "--rays" in args else 200_000
    rounds = int(args[args.index("--rounds") + 1]) if "--rounds" in args else 3
    positional = [a for i, a in enumerate(args) if not a.startswith("--") and (i == 0 or not args[i - 1].startswith("--"))]
    binary, meshes = positional[0], positional[1:]
    import open3d as o3d
    from embreex import rtcore_scene as rtcs
    from embreex.mesh_construction import TriangleMesh
    rows = []
    for path in meshes:
        mesh = o3d.io.read_triangle_mesh(path)
        V = np.asarray(mesh.vertices, dtype=np.float32); F = np.asarray(mesh.triangles, dtype=np.int64)
        o, d = rays_set(V, n)
        with tempfile.TemporaryDirectory() as tmp:
            rays_file = os.path.join(tmp, "set.rays")
            np.savetxt(rays_file, np.hstack([o, d]), fmt="%.9g")
            # Read back as proxima reads them, so every library casts the same f32 rays.
            back = np.loadtxt(rays_file, dtype=np.float32); o, d = back[:, :3].copy(), back[:, 3:].copy()
            ours = []
            for _ in range(rounds):
                out = subprocess.run([binary, "raycast", path, "--rays", rays_file, "--json", "--threads", "1"], check=True, capture_output=True, text=True)
                ours.append(json.loads(out.stdout))
            proxima_rate = max(r["rays_per_second"] for r in ours)
            csv = subprocess.run([binary, "raycast", path, "--rays", rays_file, "--threads", "1"], check=True, capture_output=True, text=True).stdout
            rust_peers_binary = os.path.join(os.path.dirname(binary), "rays_peers")
            out = subprocess.run([rust_peers_binary, path, rays_file, "--rounds", str(rounds)], check=True, capture_output=True, text=True).stdout
            rust_peers = {p["peer"]: p for p in map(json.loads, out.splitlines())}
        rows_csv = np.array([line.split(",") for line in csv.splitlines()[1:]])
        t_ours = rows_csv[:, 1].astype(np.float64)

        scene = rtcs.EmbreeScene()
        TriangleMesh(scene, V[F])
        embree_time, res = best(rounds, lambda: scene.run(o, d, output=1))
        t_embree = np.where(res["primID"] >= 0, res["tfar"], np.inf).astype(np.float64)

        o3d_scene = o3d.t.geometry.RaycastingScene()
        o3d_scene.add_triangles(o3d.core.Tensor(V), o3d.core.Tensor(F.astype(np.uint32)))
        rays_tensor = o3d.core.Tensor(np.hstack([o, d]))
        o3d_time, ans = best(rounds, lambda: o3d_scene.cast_rays(rays_tensor, nthreads=1))
        t_o3d = ans["t_hit"].numpy().astype(np.float64)

        def t_of(peer):
            return np.array([np.inf if t is None else t for t in rust_peers[peer]["t"]], dtype=np.float64)
        t_parry, t_obvhs = t_of("parry3d"), t_of("obvhs")
        parry_rate, obvhs_rate = rust_peers["parry3d"]["rays_per_second"], rust_peers["obvhs"]["rays_per_second"]

        def agree(t_peer):
            hit_ours, hit_peer = np.isfinite(t_ours), np.isfinite(t_peer)
            both = hit_ours & hit_peer
            close = np.abs(t_ours[both] - t_peer[both]) <= 1e-4 * np.maximum(t_peer[both], 1e-6)
            return int(np.sum(hit_ours != hit_peer)), int(np.sum(~close))
        peers = [agree(t) for t in (t_embree, t_o3d, t_parry, t_obvhs)]
        builds = (min(r["build_seconds"] for r in ours), rust_peers["parry3d"]["build_seconds"], rust_peers["obvhs"]["build_seconds"])
        rows.append((os.path.basename(path), len(F), n, proxima_rate, (n / embree_time, n / o3d_time, parry_rate, obvhs_rate),
                     int(np.isfinite(t_ours).sum()), peers, builds))
    names = ("Embree", "Open3D", "parry3d", "obvhs")
    print("| mesh | triangles | rays | proxima rays/s | Embree (embreex) | Open3D | parry3d | obvhs | "
          + " | ".join(f"proxima/{p}" for p in names)
          + f" | hits | hit/miss differ: {', '.join(names)} | t differs > 1e-4: {', '.join(names)} | build s: proxima, parry3d, obvhs |")
    print("|---" * 16 + "|")
    for (name, tris, n, p, rates, hits, peers, builds) in rows:
        print(f"| {name} | {tris} | {n} | {p:,.0f} | " + " | ".join(f"{r:,.0f}" for r in rates)
              + " | " + " | ".join(f"{p / r:.2f}x" for r in rates)
              + f" | {hits} | {', '.join(str(a[0]) for a in peers)} | {', '.join(str(a[1]) for a in peers)} | "
              + ", ".join(f"{b:.2f}" for b in builds) + " |")

if __name__ == "__main__":
    main()

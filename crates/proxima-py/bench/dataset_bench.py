#!/usr/bin/env python3
"""Issue 25's benchmark: proxima.dataset.sample_corpus (local and Ray engines)
against mesh_to_sdf and libigl's signed_distance driven by a
multiprocessing.Pool, on the same meshes and the same points.

Corpus: every mesh of ../shared/data (or $PROXIMA_DATA_DIR) plus generated
``proxima.noisy_icosphere(k, seed)`` meshes up to --meshes (20), written in
the --formats given, in turn (obj; glb; draco: a GLB compressed with
KHR_draco_mesh_compression by DracoPy, as Objaverse ships many files).

Phases (--phases, default all, in this order):

  local   sample_corpus(engine="local", workers=2, threads=1) into OUT/local
  ray     ray.init(num_cpus=2) (timed apart), then sample_corpus(engine="ray",
          workers=2, threads=1) into OUT/ray; outputs compared with local's;
          then the same again on the same instance into OUT/ray-warm (as on a
          long-running cluster: Ray Data's service actors already started)
  igl     igl.signed_distance(P, V, F, sign_type=FAST_WINDING_NUMBER) in a
          multiprocessing.Pool(2), one mesh per task, every point of the npz
  igl-default  the same with libigl's default sign_type (the exact,
          hierarchical winding number), on every --igl-exact-stride'th point
          (default 10), estimated as setup + query * stride (the setup timed
          by a call on one point)
  igl-pseudonormal  the same with sign_type=PSEUDONORMAL (right only on
          closed, manifold meshes), every point
  m2s     mesh_to_sdf.mesh_to_sdf(surface_point_method="sample",
          sign_method="normal") (the only headless pair: "scan" and "depth"
          render with pyrender/OpenGL), in a Pool(2). Its surface cloud
          (--m2s-cloud points, default its own default 10M) and KD-tree are built
          once per mesh (timed: "setup"), then every --m2s-stride'th point of the
          npz is queried (timed: "query"); the full 250k is estimated as
          setup + query * stride (stated in the output).
  amortized  local then Ray (ray.init apart) on the corpus repeated
          --copies times (symlinks under OUT/copies): Ray's fixed start-up cost
          (actor pool, imports; about 2.7 s a call) spread over more meshes
  memory  per mesh, a fresh process runs process_mesh once (threads=1) and
          reports VmHWM - VmRSS after import: the memory one actor needs for
          that mesh (mesh + tree + samples + output arrays)

Peers get the mesh proxima loaded (fan-triangulated polygons), normalized with
the npz's own scale/offset, and the npz's normalized points, so distances and
signs compare directly; their timings exclude reading the mesh file (their
favour), proxima's include it (and sampling and writing), and proxima's
sdf-only rate (sum of sdf_s) is given too.

Writes JSON (--json, default OUT/results.json; a phase run alone replaces only
its own entry, the others' are kept from earlier runs) and prints a table.
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[2]

#: noisy_icosphere frequencies for the generated meshes (20 k^2 triangles),
#: taken in this order until the corpus holds --meshes meshes.
ICO_FREQUENCIES = (8, 16, 24, 32, 48, 64, 96, 128, 160, 192)
#: Past those, frequencies taken in turn with a new noise seed each: 1,280 to
#: 81,920 triangles, the sizes most objects of a corpus like Objaverse have.
MORE_FREQUENCIES = (8, 12, 16, 24, 32, 48, 64)


def log(*args):
    print(*args, file=sys.stderr, flush=True)


def data_dir():
    env = os.environ.get("PROXIMA_DATA_DIR")
    path = Path(env) if env else REPO.parent / "shared" / "data"
    return path if path.is_dir() else None


def write_glb(path: Path, vertices, faces, draco: bool):
    """One triangle mesh as binary glTF: plain accessors, or (``draco``) one
    primitive compressed with KHR_draco_mesh_compression by DracoPy (16-bit
    positions), as Objaverse ships many of its files."""
    import struct

    v = np.ascontiguousarray(vertices, dtype=np.float32)
    f = np.ascontiguousarray(faces, dtype=np.uint32)
    bounds = {"min": v.min(axis=0).tolist(), "max": v.max(axis=0).tolist()}
    position = {"componentType": 5126, "count": len(v), "type": "VEC3", **bounds}
    indices = {"componentType": 5125, "count": int(f.size), "type": "SCALAR"}
    primitive = {"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}
    gltf = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0, "nodes": [{"mesh": 0}], "meshes": [{"primitives": [primitive]}]}
    if draco:
        import DracoPy

        blob = DracoPy.encode(v, f, quantization_bits=16)
        views = [{"buffer": 0, "byteOffset": 0, "byteLength": len(blob)}]
        primitive["extensions"] = {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}
        gltf["extensionsUsed"] = gltf["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    else:
        blob = v.tobytes() + f.tobytes()
        views = [{"buffer": 0, "byteOffset": 0, "byteLength": v.nbytes}, {"buffer": 0, "byteOffset": v.nbytes, "byteLength": f.nbytes}]
        position["bufferView"], indices["bufferView"] = 0, 1
    blob += b"\0" * (-len(blob) % 4)
    gltf.update(accessors=[position, indices], bufferViews=views, buffers=[{"byteLength": len(blob)}])
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(blob), 0x004E4942) + blob
    path.write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks)


def build_corpus(out: Path, n_meshes: int, formats=("obj",)):
    """The shared meshes, then generated noisy icospheres (ICO_FREQUENCIES,
    then MORE_FREQUENCIES with a seed each) up to ``n_meshes``; the generated
    ones written in ``formats`` in turn (obj, glb, draco: a Draco GLB)."""
    import proxima
    from proxima.dataset import is_mesh_file

    paths = []
    d = data_dir()
    if d is None:
        log("note: no shared data directory (../shared/data or PROXIMA_DATA_DIR); generated meshes only")
    else:
        paths = sorted(p for p in d.iterdir() if p.is_file() and is_mesh_file(p))
    gen = out / "generated"
    gen.mkdir(parents=True, exist_ok=True)
    more = ((MORE_FREQUENCIES[i % len(MORE_FREQUENCIES)], 2 + i) for i in range(n_meshes))
    sizes = [(k, 1) for k in ICO_FREQUENCIES] + list(more)
    for i, (k, seed) in enumerate(sizes):
        if len(paths) >= n_meshes:
            break
        kind = formats[i % len(formats)]
        stem = f"ico{k}" if seed == 1 else f"ico{k}s{seed}"
        path = gen / (f"{stem}.obj" if kind == "obj" else f"{stem}{'_draco' if kind == 'draco' else ''}.glb")
        if not path.exists():
            mesh = proxima.noisy_icosphere(k, seed)
            tmp = path.with_name(path.name + ".tmp")
            if kind == "obj":
                with open(tmp, "w") as f:
                    np.savetxt(f, mesh.vertices, fmt="v %.9g %.9g %.9g")
                    np.savetxt(f, np.asarray(mesh.faces) + 1, fmt="f %d %d %d")
            else:
                write_glb(tmp, mesh.vertices, mesh.faces, draco=kind == "draco")
            tmp.rename(path)
        paths.append(path)
    return paths[:n_meshes]


def mesh_info(paths):
    import proxima

    info = []
    for p in paths:
        m = proxima.load(p)
        f = m.faces
        tris = int(sum(len(x) - 2 for x in f)) if isinstance(f, list) else int(len(f) * (f.shape[1] - 2))
        info.append({"path": str(p), "name": None, "vertices": int(len(m.vertices)), "faces": len(m), "triangles": tris, "bytes": os.path.getsize(p)})
    return info


# ---------------------------------------------------------------------------
# proxima


def run_corpus(paths, out_dir: Path, engine: str, n_points: int):
    from proxima.dataset import sample_corpus

    shutil.rmtree(out_dir, ignore_errors=True)
    return sample_corpus([str(p) for p in paths], out_dir, n_points=n_points, engine=engine, workers=2, threads=1, progress=False)


def compare_outputs(a: Path, b: Path, names):
    different = []
    for name in names:
        x, y = np.load(a / f"{name}.npz"), np.load(b / f"{name}.npz")
        for key in ("points", "sdf", "scale", "offset"):
            if not np.array_equal(x[key], y[key]):
                different.append(f"{name}:{key}")
    return different


# ---------------------------------------------------------------------------
# peers (run in Pool workers)


def _triangles(faces):
    if not isinstance(faces, list):
        faces = np.asarray(faces)
        if faces.shape[1] == 3:
            return faces
        faces = list(faces)
    tris = [np.stack([np.full(len(f) - 2, f[0]), f[1:-1], f[2:]], axis=1) for f in faces]
    return np.concatenate(tris).astype(np.int64)


def _peer_input(path, npz_path):
    import proxima

    mesh = proxima.load(path)
    z = np.load(npz_path)
    V = (mesh.vertices.astype(np.float64) - z["offset"]) / float(z["scale"])
    return V, _triangles(mesh.faces), z["points"].astype(np.float64)


#: libigl sign types benchmarked: results key -> (igl enum name, label).
IGL_SIGNS = {
    "igl": ("SIGNED_DISTANCE_TYPE_FAST_WINDING_NUMBER", "libigl fast winding number"),
    "igl_default": ("SIGNED_DISTANCE_TYPE_DEFAULT", "libigl default (exact winding number)"),
    "igl_pseudonormal": ("SIGNED_DISTANCE_TYPE_PSEUDONORMAL", "libigl pseudonormal"),
}


def _igl_task(args):
    """libigl's signed_distance on every ``stride``th point. With a stride,
    a call on one point (the trees' builds and the per-call setup) is timed
    too, and the full set is estimated as setup + (query - setup) * stride."""
    path, npz_path, sign, stride = args
    os.environ["OMP_NUM_THREADS"] = "1"
    import igl

    sign_type = getattr(igl, sign)
    V, F, P = _peer_input(path, npz_path)
    Q = P[::stride]
    setup = setup_cpu = 0.0
    if stride > 1:
        t, c = time.perf_counter(), time.process_time()
        igl.signed_distance(Q[:1], V, F, sign_type=sign_type)
        setup, setup_cpu = time.perf_counter() - t, time.process_time() - c
    t, c = time.perf_counter(), time.process_time()
    s = igl.signed_distance(Q, V, F, sign_type=sign_type)
    seconds, cpu = time.perf_counter() - t, time.process_time() - c
    if stride > 1:
        seconds = setup + (seconds - setup) * len(P) / len(Q)
        cpu = setup_cpu + (cpu - setup_cpu) * len(P) / len(Q)
    return {"seconds": seconds, "cpu": cpu, "stride": stride, "sdf": np.asarray(s[0], dtype=np.float64)}


def _m2s_task(args):
    path, npz_path, stride, cloud = args
    os.environ["OMP_NUM_THREADS"] = "1"
    import trimesh
    from mesh_to_sdf import get_surface_point_cloud

    V, F, P = _peer_input(path, npz_path)
    Q = P[::stride]
    mesh = trimesh.Trimesh(V, F, process=False)
    t, c = time.perf_counter(), time.process_time()
    pc = get_surface_point_cloud(mesh, "sample", sample_point_count=cloud, calculate_normals=True)
    setup, setup_cpu = time.perf_counter() - t, time.process_time() - c
    t, c = time.perf_counter(), time.process_time()
    s = pc.get_sdf_in_batches(Q, use_depth_buffer=False)
    query, query_cpu = time.perf_counter() - t, time.process_time() - c
    return {"setup": setup, "query": query, "setup_cpu": setup_cpu, "query_cpu": query_cpu, "queried": len(Q), "total": len(P), "sdf": np.asarray(s, dtype=np.float64)}


def sign_stats(ours, theirs, n_near, idx=None):
    """Disagreements of inside (sdf < 0) between proxima and a peer."""
    idx = np.arange(len(ours)) if idx is None else idx
    a, b = ours[idx] < 0, theirs < 0
    diff = a != b
    near = idx < n_near
    far = np.abs(ours[idx]) > 0.01  # more than sigma from the surface: not a rounding tie
    return {
        "compared": int(len(idx)),
        "disagree": int(diff.sum()),
        "disagree_near": int((diff & near).sum()),
        "disagree_uniform": int((diff & ~near).sum()),
        "disagree_beyond_0.01": int((diff & far).sum()),
        "proxima_inside_peer_outside": int((diff & a).sum()),
        "max_abs_distance_diff": float(np.max(np.abs(np.abs(ours[idx]) - np.abs(theirs)))) if len(idx) else 0.0,
    }


def run_peer(kind, paths, names, npz_dir: Path, stride=1, cloud=10_000_000):
    """``kind`` "m2s" or a key of IGL_SIGNS."""
    tasks = []
    for p, n in zip(paths, names):
        npz = str(npz_dir / f"{n}.npz")
        tasks.append((str(p), npz, stride, cloud) if kind == "m2s" else (str(p), npz, IGL_SIGNS[kind][0], stride))
    fn = _m2s_task if kind == "m2s" else _igl_task
    ctx = mp.get_context("spawn")
    t = time.perf_counter()
    with ctx.Pool(2) as pool:
        results = pool.map(fn, tasks, chunksize=1)
    wall = time.perf_counter() - t
    per_mesh = {}
    for n, r in zip(names, results):
        z = np.load(npz_dir / f"{n}.npz")
        ours, n_near = z["sdf"].astype(np.float64), int(z["n_near"])
        idx = None if stride == 1 else np.arange(0, len(ours), stride)
        row = {k: v for k, v in r.items() if k != "sdf"}
        row["signs"] = sign_stats(ours, r["sdf"], n_near, idx)
        per_mesh[n] = row
    return wall, per_mesh


# ---------------------------------------------------------------------------
# memory per actor

_MEM_CHILD = r"""
import json, sys, tempfile
def status(key):
    for line in open('/proc/self/status'):
        if line.startswith(key + ':'):
            return int(line.split()[1]) * 1024
import numpy, proxima
from proxima.dataset import Options, process_mesh
import os, time
base = status('VmRSS')
with tempfile.TemporaryDirectory() as d:
    t, c = time.perf_counter(), time.process_time()
    s = process_mesh(sys.argv[1], sys.argv[2], d, Options(n_points=int(sys.argv[3])), threads=1)
    wall, cpu = time.perf_counter() - t, time.process_time() - c
    size = os.path.getsize(os.path.join(d, sys.argv[2] + '.npz'))
print(json.dumps({'base': base, 'hwm': status('VmHWM'), 'status': s['status'], 'wall': wall, 'cpu': cpu, 'npz_bytes': size,
                  **{k: s[k] for k in ('load_s', 'sample_s', 'sdf_s', 'write_s')}}))
"""


def run_memory(paths, names, n_points):
    out = {}
    for p, n in zip(paths, names):
        r = subprocess.run([sys.executable, "-c", _MEM_CHILD, str(p), n, str(n_points)], capture_output=True, text=True)
        if r.returncode != 0:
            out[n] = {"error": r.stderr[-300:]}
            continue
        d = json.loads(r.stdout.strip().splitlines()[-1])
        d["delta"] = d["hwm"] - d["base"]
        out[n] = d
    return out


# ---------------------------------------------------------------------------


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(REPO / "target" / "dataset-bench"))
    ap.add_argument("--meshes", type=int, default=20)
    ap.add_argument("--formats", default="obj", help="formats of the generated meshes, in turn: obj, glb, draco (a Draco GLB; needs DracoPy)")
    ap.add_argument("--points", type=int, default=250_000)
    ap.add_argument("--phases", default="local,ray,amortized,igl,igl-default,igl-pseudonormal,m2s,memory")
    ap.add_argument("--igl-exact-stride", type=int, default=10, help="query every Nth point with libigl's default (exact winding number) sign and scale")
    ap.add_argument("--m2s-stride", type=int, default=10, help="query every Nth point with mesh_to_sdf and scale")
    ap.add_argument("--m2s-cloud", type=int, default=10_000_000, help="mesh_to_sdf's surface sample count (its default 10M)")
    ap.add_argument("--copies", type=int, default=5, help="corpus repetitions of the 'amortized' phase")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    phases = args.phases.split(",")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    json_path = Path(args.json) if args.json else out / "results.json"
    results = json.loads(json_path.read_text()) if json_path.exists() else {}
    results["machine"] = {"cpus": os.cpu_count(), "python": platform.python_version(), "time": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}

    import proxima
    from proxima.dataset import mesh_names

    paths = build_corpus(out, args.meshes, tuple(args.formats.split(",")))
    names = mesh_names(paths)
    info = mesh_info(paths)
    for i, n in zip(info, names):
        i["name"] = n
    results["corpus"] = info
    results["points"] = args.points
    results["out"] = str(out)
    log(f"corpus: {len(paths)} meshes, {sum(i['triangles'] for i in info):,} triangles")

    def save():
        json_path.write_text(json.dumps(results, indent=1))

    cores = 2
    if "local" in phases:
        log("local engine ...")
        s = run_corpus(paths, out / "local", "local", args.points)
        results["local"] = s
        save()
        log(f"  {s['seconds']:.1f} s, {s['samples_per_second_per_core']:.0f} samples/s/core")
    if "ray" in phases:
        import ray

        log("ray engine ...")
        t = time.perf_counter()
        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
        ray_start = time.perf_counter() - t
        s = run_corpus(paths, out / "ray", "ray", args.points)
        # Again on the same instance, as on a long-running cluster: Ray Data's
        # per-cluster service actors exist by now, the actor pool starts anew.
        warm = run_corpus(paths, out / "ray-warm", "ray", args.points)
        ray.shutdown()
        s["warm"] = {k: warm[k] for k in ("seconds", "samples_per_second_per_core", "mesh_seconds")}
        s["ray_init_seconds"] = ray_start
        if (out / "local").is_dir():
            s["differs_from_local"] = compare_outputs(out / "local", out / "ray", names)
        results["ray"] = s
        save()
        log(f"  ray.init {ray_start:.1f} s; {s['seconds']:.1f} s, {s['samples_per_second_per_core']:.0f} samples/s/core")
    npz_dir = out / "local"
    for key, (_, label) in IGL_SIGNS.items():
        phase = key.replace("_", "-")
        if phase not in phases:
            continue
        stride = args.igl_exact_stride if key == "igl_default" else 1
        log(f"{label}, Pool(2), every {stride}th point ...")
        wall, per = run_peer(key, paths, names, npz_dir, stride=stride)
        results[key] = {"wall": wall, "stride": stride, "samples": args.points * len(paths), "per_mesh": per}
        save()
        log(f"  {wall:.1f} s wall")
    if "m2s" in phases:
        log(f"mesh_to_sdf sample/normal, cloud {args.m2s_cloud}, every {args.m2s_stride}th point, Pool(2) ...")
        wall, per = run_peer("m2s", paths, names, npz_dir, stride=args.m2s_stride, cloud=args.m2s_cloud)
        est = sum(r["setup"] + r["query"] * r["total"] / r["queried"] for r in per.values())
        est_cpu = sum(r["setup_cpu"] + r["query_cpu"] * r["total"] / r["queried"] for r in per.values())
        results["m2s"] = {"wall": wall, "stride": args.m2s_stride, "cloud": args.m2s_cloud, "estimated_cpu_seconds_full": est, "estimated_process_cpu_seconds_full": est_cpu, "samples": args.points * len(paths), "per_mesh": per}
        save()
        log(f"  {wall:.1f} s wall on the subset; full estimate {est:.0f} process-seconds")
    if "amortized" in phases:
        import ray

        src = out / "copies" / "src"
        shutil.rmtree(out / "copies", ignore_errors=True)
        src.mkdir(parents=True)
        for p, n in zip(paths, names):
            suffix = "".join(Path(p).suffixes[-2:]) if str(p).endswith(".gz") else Path(p).suffix
            for i in range(args.copies):
                os.symlink(os.path.abspath(p), src / f"{n}_{i}{suffix}")
        copies = sorted(src.iterdir())
        log(f"amortized: {len(copies)} meshes, local then ray ...")
        am = {"meshes": len(copies)}
        for engine in ("local", "ray"):
            if engine == "ray":
                ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
            s = run_corpus(copies, out / "copies" / engine, engine, args.points)
            if engine == "ray":
                ray.shutdown()
            am[engine] = {k: s[k] for k in ("seconds", "samples_per_second_per_core", "mesh_seconds")}
        shutil.rmtree(out / "copies", ignore_errors=True)
        results["amortized"] = am
        save()
    if "memory" in phases:
        log("memory per mesh (fresh process each) ...")
        results["memory"] = run_memory(paths, names, args.points)
        save()
    report(results, names)
    save()


def report(r, names):
    rows = []
    n = r["points"] * len(r["corpus"])
    cores = 2
    loc = r.get("local")
    if loc:
        rows.append(("proxima local (load+sample+sdf+write)", loc["samples_per_second_per_core"]))
        rows.append(("proxima local, sdf_s only", loc["samples"] / loc["mesh_seconds"]["sdf_s"]))
    if r.get("ray"):
        rows.append(("proxima ray (after ray.init)", r["ray"]["samples_per_second_per_core"]))
        if "warm" in r["ray"]:
            rows.append(("proxima ray, second call on the same instance", r["ray"]["warm"]["samples_per_second_per_core"]))
    mem = [m for m in r.get("memory", {}).values() if "cpu" in m]
    if len(mem) == len(r["corpus"]):
        rows.append(("proxima process_mesh, per CPU-second", n / sum(m["cpu"] for m in mem)))
    for key, (_, label) in IGL_SIGNS.items():
        if not r.get(key):
            continue
        per = r[key]["per_mesh"].values()
        suffix = f", est. from 1/{r[key]['stride']}" if r[key].get("stride", 1) > 1 else ""
        if r[key].get("stride", 1) == 1:
            rows.append((f"{label}, Pool(2), wall", n / r[key]["wall"] / cores))
        rows.append((f"{label}, per busy process-s{suffix}", n / sum(m["seconds"] for m in per)))
        if all("cpu" in m for m in per):
            rows.append((f"{label}, per CPU-s{suffix}", n / sum(m["cpu"] for m in per)))
    if r.get("m2s"):
        rows.append(("mesh_to_sdf sample/normal, est., per busy s", n / r["m2s"]["estimated_cpu_seconds_full"]))
        if "estimated_process_cpu_seconds_full" in r["m2s"]:
            rows.append(("mesh_to_sdf sample/normal, est., per CPU-s", n / r["m2s"]["estimated_process_cpu_seconds_full"]))
    base = rows[0][1] if rows else 1.0
    print(f"{'method':60s} {'samples/s/core':>15s} {'proxima local / this':>22s}")
    for name, rate in rows:
        print(f"{name:60s} {rate:15,.0f} {base / rate:22.2f}")
    if loc and r.get("ray"):
        print(f"Ray overhead vs local: {100 * (1 - r['ray']['samples_per_second_per_core'] / loc['samples_per_second_per_core']):.1f}% "
              f"(ray.init {r['ray']['ray_init_seconds']:.1f} s apart; outputs differ: {r['ray'].get('differs_from_local')})")
    am = r.get("amortized")
    if am:
        print(f"Ray overhead vs local on {am['meshes']} meshes: "
              f"{100 * (1 - am['ray']['samples_per_second_per_core'] / am['local']['samples_per_second_per_core']):.1f}% "
              f"(local {am['local']['samples_per_second_per_core']:,.0f}, ray {am['ray']['samples_per_second_per_core']:,.0f} samples/s/core)")
    peers = [k for k in (*IGL_SIGNS, "m2s") if r.get(k)]
    print("sign disagreements with proxima (all / beyond 0.01 of the surface) per peer: " + ", ".join(peers))
    print(f"{'mesh':22s} {'tris':>8s} " + " ".join(f"{k[:16]:>17s}" for k in peers) + f" {'MiB/actor':>9s} {'npz MiB':>7s}")
    for i in r["corpus"]:
        name = i["name"]
        cells = []
        for k in peers:
            g = r[k]["per_mesh"].get(name, {}).get("signs", {})
            cells.append(f"{g.get('disagree', '-')}/{g.get('disagree_beyond_0.01', '-')}")
        mem = r.get("memory", {}).get(name, {}).get("delta")
        npz = Path(r.get("out", "")) / "local" / f"{name}.npz"
        print(f"{name:22s} {i['triangles']:8d} " + " ".join(f"{c:>17s}" for c in cells)
              + f" {(mem or 0) / 2**20:9.0f} {npz.stat().st_size / 2**20 if npz.exists() else 0:7.2f}")

if __name__ == "__main__":
    main()

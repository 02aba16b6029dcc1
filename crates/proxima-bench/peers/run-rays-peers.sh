#!/usr/bin/env bash
# First-hit rays: proxima against Embree (embreex), Open3D, parry3d and obvhs,
# one core, one run.
#
#   crates/proxima-bench/peers/run-rays-peers.sh [MESH.ply ...]
#
# Default meshes: dragon_vrip.ply.gz (decompressed to a temporary PLY, found
# through PROXIMA_DATA_DIR, else ../shared/data) and ico1m (exported by
# sdf_compare). Environment: RAYS (200000) rays per mesh, PEERS_VENV (the
# virtual environment, target/peers-venv). Builds `proxima` and the
# proxima-bench binaries (`rays_peers`: parry3d and obvhs) in release, then
# runs rays_peers.py pinned to core 0; prints one table.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../../.." && pwd)
venv=${PEERS_VENV:-$root/target/peers-venv}
rays=${RAYS:-200000}
data=${PROXIMA_DATA_DIR:-$root/../shared/data}
packages=(numpy==2.4.6 open3d-cpu==0.20.0 embreex==4.4.0.post1)
if ! "$venv/bin/python" -c 'import numpy, open3d, embreex' 2>/dev/null; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet --upgrade pip
    "$venv/bin/pip" install --quiet "${packages[@]}"
fi
pin=()
command -v taskset >/dev/null && pin=(taskset -c 0)
export OMP_NUM_THREADS=1 RAYON_NUM_THREADS=1
(cd "$root" && cargo build --release --quiet -p proxima-cli -p proxima-bench)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
    gunzip -c "$data/dragon_vrip.ply.gz" >"$work/dragon_vrip.ply"
    "$root/target/release/sdf_compare" ico1m --queries 100 --rounds 1 --check 10 --export "$work" >/dev/null
    mv "$work/ico1m/mesh.ply" "$work/ico1m.ply"
    meshes=("$work/dragon_vrip.ply" "$work/ico1m.ply")
fi
echo "# $(date -u +%Y-%m-%dT%H:%MZ), $(git -C "$root" rev-parse --short HEAD), load average $(cut -d' ' -f1-3 /proc/loadavg), pinned to core 0, $rays rays per mesh"
"${pin[@]}" "$venv/bin/python" "$here/rays_peers.py" "$root/target/release/proxima" "${meshes[@]}" --rays "$rays"

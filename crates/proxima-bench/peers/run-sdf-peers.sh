#!/usr/bin/env bash
# Signed distance: proxima against Open3D and libigl, one core, in one run.
#
#   crates/proxima-bench/peers/run-sdf-peers.sh [MESH|ico1m ...]
#
# Default meshes: dragon_vrip.ply.gz (found through PROXIMA_DATA_DIR, else
# ../shared/data beside the checkout) and ico1m. Environment:
#   QUERIES (20000)        points per query set (near, uniform)
#   CHECK (500)            points per set checked against the exact winding number
#   LIBIGL_QUERIES (20000) points per set given to libigl (each call rebuilds its trees)
#   PEERS_VENV             the Python virtual environment (target/peers-venv)
#   SDF_PEERS_DIR          the export folder (target/sdf-peers)
# Builds sdf_compare, runs it pinned to core 0 with --export, then
# sdf_peers.py pinned to the same core with every thread pool at one
# thread. Prints the tables for docs/perf-log.md; the whole output is also
# kept in $SDF_PEERS_DIR/report.txt. Exits non-zero when proxima's signs
# disagree with the exact winding number (after printing everything).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../../.." && pwd)
venv=${PEERS_VENV:-$root/target/peers-venv}
out=${SDF_PEERS_DIR:-$root/target/sdf-peers}
queries=${QUERIES:-20000}
check=${CHECK:-500}
libigl_queries=${LIBIGL_QUERIES:-20000}
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
    meshes=(dragon_vrip.ply.gz ico1m)
fi

# Versions that install and run here (Python 3.11, x86_64 Linux).
packages=(numpy==2.4.6 open3d-cpu==0.20.0 libigl==2.6.3)
if ! "$venv/bin/python" -c 'import numpy, igl' 2>/dev/null; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install --quiet --upgrade pip
    "$venv/bin/pip" install --quiet "${packages[@]}"
fi
# Open3D's module links libusb even without a device.
if ! "$venv/bin/python" -c 'import open3d' 2>/dev/null; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        apt-get install -y -qq libusb-1.0-0 >/dev/null || { apt-get update -qq && apt-get install -y -qq libusb-1.0-0 >/dev/null; }
    fi
    "$venv/bin/python" -c 'import open3d' || { echo "run-sdf-peers: open3d does not import (libusb-1.0-0 missing?)" >&2; exit 1; }
fi

pin=()
if command -v taskset >/dev/null; then
    pin=(taskset -c 0)
else
    echo "run-sdf-peers: no taskset, the runs are not pinned to one core" >&2
fi
export OMP_NUM_THREADS=1 MKL_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 IGL_NUM_THREADS=1 RAYON_NUM_THREADS=1

(cd "$root" && cargo build --release --quiet -p proxima-bench --bin sdf_compare)
mkdir -p "$out"
start=$(date +%s)
rm -f "$out/status"
{
    echo "# $(date -u +%Y-%m-%dT%H:%MZ), $(git -C "$root" rev-parse --short HEAD), $(getconf _NPROCESSORS_ONLN) cores, runs pinned to core 0"
    echo "# load average $(cut -d' ' -f1-3 /proc/loadavg) (other processes share the cores)"
    echo "# QUERIES=$queries CHECK=$check LIBIGL_QUERIES=$libigl_queries $0 ${meshes[*]}"
    "${pin[@]}" "$root/target/release/sdf_compare" "${meshes[@]}" --queries "$queries" --check "$check" --export "$out" || echo $? >"$out/status"
    names=()
    for mesh in "${meshes[@]}"; do
        name=$(basename "$mesh")
        names+=("${name%%.*}")
    done
    "${pin[@]}" "$venv/bin/python" "$here/sdf_peers.py" "$out" "${names[@]}" --libigl-queries "$libigl_queries"
    echo "# wall time $(($(date +%s) - start)) s"
} 2>&1 | tee "$out/report.txt"
# The tables are printed either way; a sign error of proxima's still fails the run.
[ ! -e "$out/status" ] || exit "$(cat "$out/status")"

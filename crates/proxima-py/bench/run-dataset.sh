#!/usr/bin/env bash
# The dataset benchmark (issue 25): creates its venv if absent
# (target/py-dataset-venv), installs Ray, mesh_to_sdf and libigl
# (requirements-dataset.txt) and proxima (../, no build isolation), then runs
# dataset_bench.py with the arguments given (e.g. --phases local,ray --points 50000).
# PROXIMA_BENCH_SKIP_INSTALL=1 skips the proxima install (already current).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
venv="${PROXIMA_DATASET_VENV:-$repo/target/py-dataset-venv}"
source "$repo/scripts/python-venv.sh"
proxima_venv "$venv" "$here/requirements-dataset.txt"
proxima_bench_install "$venv"
exec "$venv/bin/python" "$here/dataset_bench.py" "$@"

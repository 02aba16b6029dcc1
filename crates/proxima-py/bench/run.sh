#!/usr/bin/env bash
# The Python benchmark: creates its venv if absent (target/py-bench-venv),
# installs the peers (requirements.txt) and proxima (../, no build isolation),
# then runs bench.py with the arguments given (e.g. --quick, --json PATH).
# PROXIMA_BENCH_SKIP_INSTALL=1 skips the proxima install (already current).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../../.." && pwd)"
venv="${PROXIMA_BENCH_VENV:-$repo/target/py-bench-venv}"
source "$repo/scripts/python-venv.sh"
proxima_venv "$venv" "$here/requirements.txt"
# Open3D's wheel links libusb-1.0, which slim Debian images lack.
if ! "$venv/bin/python" -c "import open3d" >/dev/null 2>&1; then
    if ! ldconfig -p | grep -q libusb-1.0 && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
        echo "installing libusb-1.0-0 for Open3D" >&2
        (apt-get install -y -qq libusb-1.0-0 || { apt-get update -qq && apt-get install -y -qq libusb-1.0-0; }) >/dev/null
    fi
    "$venv/bin/python" -c "import open3d" >/dev/null 2>&1 || echo "note: open3d does not import; its rows will be skipped" >&2
fi
proxima_bench_install "$venv"
exec "$venv/bin/python" "$here/bench.py" "$@"

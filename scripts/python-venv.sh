# Sourced by scripts/test and the Python benchmarks' run scripts: the one way
# this project makes a virtual environment with the proxima package in it.
#
#   proxima_venv VENV REQUIREMENTS...   makes VENV if absent, puts its bin first
#                                       on PATH, installs maturin and the
#                                       requirements files
#   proxima_install VENV                builds and installs crates/proxima-py
#                                       into VENV (release, maturin)
#   proxima_bench_install VENV          the same, for the benchmarks' run
#                                       scripts: skipped when
#                                       PROXIMA_BENCH_SKIP_INSTALL=1
#
# maturin is installed into the venv (rather than pip making an isolated
# build environment each time) so that builds reuse cargo's target directory;
# its PEP 517 backend runs `maturin` from PATH, hence the PATH change.

proxima_repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

proxima_venv() {
  local venv="$1"
  shift
  if [ ! -x "$venv/bin/python" ]; then
    echo "creating $venv" >&2
    "${PYTHON:-python3}" -m venv "$venv"
  fi
  export PATH="$venv/bin:$PATH"
  local requirements=()
  for file in "$@"; do
    requirements+=(-r "$file")
  done
  "$venv/bin/python" -m pip install --quiet "maturin>=1.9,<2" "${requirements[@]}"
}

proxima_install() {
  "$1/bin/python" -m pip install --quiet --no-build-isolation --no-deps --force-reinstall "$proxima_repo/crates/proxima-py"
}

proxima_bench_install() {
  if [ "${PROXIMA_BENCH_SKIP_INSTALL:-0}" != 1 ]; then
    echo "installing proxima from $proxima_repo/crates/proxima-py (maturin, release build)" >&2
    proxima_install "$1"
  fi
}

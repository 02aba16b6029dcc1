#!/usr/bin/env bash
# Runs every libFuzzer target for SECONDS seconds each (default 60), one after
# the other, and prints the executions per target. Usage: fuzz/run.sh [SECONDS] [TARGET...]
#
# - Installs cargo-fuzz if missing (`cargo install cargo-fuzz --locked`, about 1.5 min).
# - Safe Rust needs no memory sanitizer: targets are built with `--sanitizer none`,
#   optimized, with debug assertions on (`-a`). On a stable toolchain cargo-fuzz's
#   nightly-only flags are allowed through RUSTC_BOOTSTRAP=1.
# - Seeds: fuzz/seeds (tiny hand-written files in every format) plus the real meshes
#   of ../shared/data cut to 64 KiB, gzip-compressed for load_gzip. Corpora grow in
#   fuzz/corpus/<target> (not committed); crashes land in fuzz/artifacts/<target>.
#   Copy a crash into fuzz/regressions/<target>/ and the test
#   fuzz_smoke::saved_fuzz_failures_stay_fixed replays it from then on.
set -euo pipefail
cd "$(dirname "$0")"
seconds=${1:-60}
shift || true
all=(load_obj load_ply load_stl load_off load_glb load_gzip aabb_tree wide_tree hash_grid traversal)
targets=("${@:-${all[@]}}")
if [ $# -eq 0 ]; then targets=("${all[@]}"); fi

command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked
export RUSTC_BOOTSTRAP=1

shared=../../shared/data
[ -d "$shared" ] || shared=../../../shared/data
mkdir -p corpus logs
seed() { # seed TARGET EXTENSION [gzip FORMAT_BYTE]
    local dir=corpus/$1 ext=$2
    mkdir -p "$dir"
    for f in seeds/*"$ext" "$shared"/*"$ext"; do
        [ -f "$f" ] || continue
        local name
        name=$(basename "$f")
        if [ "${3:-}" = gzip ]; then
            { printf "\\x$4"; head -c 65536 "$f" | gzip -c; } > "$dir/$name.gz"
        else
            head -c 65536 "$f" > "$dir/$name"
        fi
    done
}
seed load_obj .obj; seed load_ply .ply; seed load_stl .stl; seed load_off .off; seed load_glb .glb
seed load_gzip .obj gzip 00; seed load_gzip .ply gzip 01; seed load_gzip .stl gzip 02; seed load_gzip .off gzip 03; seed load_gzip .glb gzip 04
for t in aabb_tree wide_tree hash_grid traversal; do mkdir -p corpus/$t; done

cargo fuzz build --sanitizer none -a
status=0
for t in "${targets[@]}"; do
    echo "== $t (${seconds}s)"
    if cargo fuzz run --sanitizer none -a "$t" "corpus/$t" -- \
        -max_total_time="$seconds" -max_len=1048576 -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
        > "logs/$t.log" 2>&1; then
        result=ok
    else
        result="CRASH (see fuzz/logs/$t.log and fuzz/artifacts/$t)"
        status=1
    fi
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "logs/$t.log" | grep -o '[0-9]*$' || echo '?')
    echo "$t: $runs executions, $result"
done
exit $status

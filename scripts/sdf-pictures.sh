#!/usr/bin/env bash
# Renders the pictures of docs/sdf.md with the viewer's scripted mode: for a
# mesh with holes and a self-intersecting mesh, the signed-distance slice
# with the side decided by the winding number and by pseudonormals, side by
# side (the side panel cropped away). Needs xvfb-run (or a DISPLAY) and
# ImageMagick's `convert`.
#
#   scripts/sdf-pictures.sh [DATA_DIR] [OUT_DIR]
#
# DATA_DIR defaults to $PROXIMA_DATA_DIR or ../shared/data; OUT_DIR to docs/images.
# The inside-cell counts of each slice (from the screenshots' JSON sidecars)
# are printed: they are the figures quoted in docs/sdf.md.
set -euo pipefail
cd "$(dirname "$0")/.."
data=${1:-${PROXIMA_DATA_DIR:-../shared/data}}
out=${2:-docs/images}
cargo build --release -q -p proxima-cli
cargo build --release -q -p proxima-viewer --example overlapping_spheres --example side_by_side
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
./target/release/examples/overlapping_spheres "$work/overlapping-spheres.obj"
if [ -n "${DISPLAY:-}" ]; then launcher=(); else launcher=(xvfb-run -a -s "-screen 0 1280x800x24"); fi
run() { # NAME MESH VIEW-ARGS...
  local name=$1 mesh=$2
  shift 2
  for sign in winding pseudonormal; do
    XDG_RUNTIME_DIR=$work "${launcher[@]}" ./target/release/proxima view "$mesh" --size 860x560 --frames 3 --slice-sign "$sign" "$@" \
      --screenshot "$work/$name-$sign.png" >/dev/null
    printf '%s %s: %s of %s slice cells inside\n' "$name" "$sign" \
      "$(sed -n 's/.*"slice_inside": \([0-9]*\).*/\1/p' "$work/$name-$sign.png.json")" \
      "$(sed -n 's/.*"slice_cells": \([0-9]*\).*/\1/p' "$work/$name-$sign.png.json")"
  done
  # The 3D views only: the side panel is 340 points wide.
  ./target/release/examples/side_by_side 340 "$work/$name-winding.png" "$work/$name-pseudonormal.png" \
    "$out/sdf-$name.png"
}
# The teapot: open (10 boundary loops), 4 components, unwelded patch seams.
# The query point inside the body, in the slice's plane.
run holes "$data/teapot.obj" --slice z,0.3 --camera 0,0 --query 0,1,0.3
# The query point inside the left sphere, next to the right one's buried surface.
run self-intersecting "$work/overlapping-spheres.obj" --slice z --camera 0,0 --query -0.6,0,0
ls -l "$out"/sdf-*.png

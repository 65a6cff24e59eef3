#!/usr/bin/env bash
# Meshes the warhead example and renders it with pvbatch under xvfb-run, as the main job does;
# checks the PNGs are real pictures, and that a missing input fails with one line.
# Usage: test_render.sh HEXDEM SOURCE_DIR WORK_DIR
set -euo pipefail
hexdem=$1 src=$2 work=$3
mkdir -p "$work"
rm -f "$work"/*.png "$work"/*.vtu
"$hexdem" mesh "$src/cases/warhead/outline.toml" --axisymmetric -q -o "$work/warhead.vtu"
render() { "$src/scripts/pvbatch-xvfb.sh" "$src/scripts/render_lattice.py" "$@"; }
render "$work/warhead.vtu" "$work/full.png" --color body
render "$work/warhead.vtu" "$work/detail.png" --color kind --zoom 0 -0.004 0.016 0.016
/usr/bin/python3 "$src/tests/cli/check_png.py" "$work/full.png" 1280 960
/usr/bin/python3 "$src/tests/cli/check_png.py" "$work/detail.png" 1280 960 3 0.3
if render "$work/missing.vtu" "$work/missing.png" 2> "$work/err.txt"; then
  echo "rendering a missing file did not fail"; exit 1
fi
grep -q "missing.vtu" "$work/err.txt" || { echo "error does not name the file:"; cat "$work/err.txt"; exit 1; }
[ ! -e "$work/missing.png" ] || { echo "PNG written for a missing input"; exit 1; }
echo "render test passed"

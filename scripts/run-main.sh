#!/usr/bin/env bash
# The main job: installs what is missing, builds hexdem, meshes the bundled example outlines
# and renders PNG pictures of the lattices with pvbatch. Output: hexdem-output/ (or $1).
# Usage (as root on Debian 12): scripts/run-main.sh [OUTPUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-hexdem-output}
mkdir -p "$out"
out=$(cd "$out" && pwd)

scripts/setup-deps.sh
scripts/build.sh release
hexdem=build/release/solver/hexdem

"$hexdem" --version
"$hexdem" mesh cases/halfplane/outline.toml -o "$out/halfplane.vtu"
"$hexdem" mesh cases/narrow_plate/outline.toml -o "$out/narrow_plate.vtu"
"$hexdem" mesh cases/warhead/outline.toml --axisymmetric -o "$out/warhead.vtu"
# An elastic run: the paper's narrow plate under the Eq. 23 ramp (about 2 s).
"$hexdem" run cases/narrow_plate/case.toml --out "$out"

# xvfb-run -a can lose a race for a display number with another X server starting at the
# same moment ("bad X server connection"): try again before giving up.
render() {
  local attempt
  for attempt in 1 2 3; do
    if xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch scripts/render_lattice.py "$@"; then return 0; fi
    [ -e "${1:-}" ] || return 1   # a missing input is not worth retrying
    echo "render: attempt $attempt failed, retrying" >&2
    sleep 2
  done
  return 1
}
render "$out/warhead.vtu" "$out/warhead.png" --color body
render "$out/warhead.vtu" "$out/warhead_detail.png" --color kind --zoom 0 -0.004 0.016 0.016
render "$out/halfplane.vtu" "$out/halfplane_load.png" --color load --zoom 0 -0.012 0.03 0.001

cat <<MSG

Done. Lattices and pictures are in $out:
$(cd "$out" && ls -1 *.vtu *.pvd *.csv *.png | sed 's/^/  /')
Open a lattice in ParaView: paraview $out/warhead.vtu
Open the narrow plate's time series: paraview $out/narrow_plate.pvd (colour by "stress", component YY)
(points are disk centres: choose the "Point Gaussian" representation with Scale Array
"radius"; lines are bonds, coloured by "bond_class").
MSG

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
# Elastic runs: the paper's narrow plate under the Eq. 23 ramp, and the half-plane under the
# Eq. 21 pulse (72,395 disks to t = 104 us), with its tau_max / p_max figure (Fig. 4).
"$hexdem" run cases/narrow_plate/case.toml --out "$out"
"$hexdem" run cases/halfplane/case.toml --out "$out"
cases/halfplane/figures.sh "$out"

render() { scripts/pvbatch-xvfb.sh scripts/render_lattice.py "$@"; }
render "$out/warhead.vtu" "$out/warhead.png" --color body
render "$out/warhead.vtu" "$out/warhead_detail.png" --color kind --zoom 0 -0.004 0.016 0.016
render "$out/halfplane.vtu" "$out/halfplane_load.png" --color load --zoom 0 -0.012 0.03 0.001

cat <<MSG

Done. Lattices and pictures are in $out:
$(cd "$out" && ls -1 *.vtu *.pvd *.csv *.png | sed 's/^/  /')
Open a lattice in ParaView: paraview $out/warhead.vtu
Open a time series: paraview $out/halfplane.pvd (colour by "stress"; or apply the hexdem
filters after loading the plugin: Tools > Manage Plugins > Load New >
$(ls "$PWD"/build/release/lib/paraview-5.11/plugins/HexDEMFilters/HexDEMFilters.so))
(points are disk centres: choose the "Point Gaussian" representation with Scale Array
"radius"; lines are bonds, coloured by "bond_class").
MSG

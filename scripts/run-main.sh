#!/usr/bin/env bash
# The main job: installs what is missing, builds hexdem, and runs case 4 of the validation
# suite, the steel warhead into a concrete disc (paper Section 5.3), at 100 m/s and, for the
# comparison figures, at 50 and 25 m/s (full size, 8,716 disks each, 2 threads: well under a
# minute each on an idle 2-core machine); then its numbers and figures. Also meshes the
# warhead's outline and renders two pictures of the lattice.
# Output: hexdem-output/ (or $1): the .pvd series with their frames, the CSV histories, the
# summary and the PNG figures, all in that one folder.
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

# The lattice of the case (the pictures in the top-level README), with the case's own
# [mesh] jitter and jitter_seed, read from case.toml so that the picture cannot drift from it.
read -r jitter jitter_seed < <(/usr/bin/python3 -c '
import tomllib
m = tomllib.load(open("cases/warhead/case.toml", "rb"))["mesh"]
print(m.get("jitter", 0), m.get("jitter_seed", 1))')
"$hexdem" mesh cases/warhead/outline.toml --axisymmetric --jitter "$jitter" --jitter-seed "$jitter_seed" \
  -o "$out/warhead_lattice.vtu"
render() { scripts/pvbatch-xvfb.sh scripts/render_lattice.py "$@"; }
render "$out/warhead_lattice.vtu" "$out/warhead_lattice.png" --color body
render "$out/warhead_lattice.vtu" "$out/warhead_lattice_detail.png" --color kind --zoom 0 -0.004 0.016 0.016

# Case 4 at 100, 50 and 25 m/s, analysis and figures; prints where everything is and how to
# open it in ParaView with the plugin.
HEXDEM="$PWD/$hexdem" THREADS=2 cases/warhead/run_all.sh "$out"

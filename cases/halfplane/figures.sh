#!/usr/bin/env bash
# Figures of the half-plane case from a finished run of case.toml: tau_max / p_max at
# t = 104 us (the paper's Fig. 4) and the same with the predicted wave fronts labelled.
# Usage: cases/halfplane/figures.sh OUTPUT_DIR   (the --out folder of hexdem run)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:?usage: figures.sh OUTPUT_DIR}
series="$out/halfplane.pvd"
[ -f "$series" ] || { echo "figures.sh: $series: no such file (run the case first)" >&2; exit 2; }
plugin=${HEXDEM_PLUGIN:-$(ls "$root"/build/*/lib/paraview-5.11/plugins/HexDEMFilters/HexDEMFilters.so 2>/dev/null | head -n 1)}
[ -n "$plugin" ] || { echo "figures.sh: HexDEMFilters plugin not built (scripts/build.sh release)" >&2; exit 2; }
HEXDEM_PLUGIN="$plugin" "$root/scripts/pvbatch-xvfb.sh" "$root/vtkfilters/scripts/figure_max_shear.py" \
  "$series" "$out/halfplane_tau_max.png" --time 104e-6 --range 0 0.3
echo "figure: $out/halfplane_tau_max.png"
HEXDEM_PLUGIN="$plugin" "$root/scripts/pvbatch-xvfb.sh" "$here/figure_fronts.py" \
  "$series" "$out/halfplane_fronts.png" --time 104e-6 --range 0 0.3
echo "figure: $out/halfplane_fronts.png"

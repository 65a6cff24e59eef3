#!/usr/bin/env bash
# Renders the three figures (maximum shear, cracks, fragments) with pvbatch under xvfb-run on
# the synthetic frames, as the cases do; checks the PNGs are real pictures, and that a
# missing input fails with one line naming it and writes no PNG.
# Usage: test_figures.sh SOURCE_DIR FRAMES_DIR PLUGIN WORK_DIR
set -euo pipefail
src=$1 frames=$2 plugin=$3 work=$4
scripts=$src/vtkfilters/scripts
mkdir -p "$work"
rm -f "$work"/*.png
render() { "$src/scripts/pvbatch-xvfb.sh" "$@" --plugin "$plugin"; }
check() { /usr/bin/python3 "$src/tests/cli/check_png.py" "$@"; }

render "$scripts/figure_max_shear.py" "$frames/fractured.vtu" "$work/max_shear.png" --range 0 0.1
render "$scripts/figure_max_shear.py" "$frames/series.pvd" "$work/max_shear_3d.png" --time 1e-5 \
  --3d --zoom 0 0 0.01 0.008 --size 800 600
render "$scripts/figure_cracks.py" "$frames/fractured.vtu" "$work/cracks.png"
render "$scripts/figure_cracks.py" "$frames/fractured.vtu" "$work/cracks_detail.png" \
  --zoom 0.01 0.05 0.04 0.07 --disks damage --max-break-time 9e-5
render "$scripts/figure_fragments.py" "$frames/fractured.vtu" "$work/fragments.png"
render "$scripts/figure_fragments.py" "$frames/series.pvd" "$work/fragments_series.png" --time 2e-5
check "$work/max_shear.png" 1280 960 20 0.3
check "$work/max_shear_3d.png" 800 600 10 0.3
check "$work/cracks.png" 1280 960 5 0.3
check "$work/cracks_detail.png" 1280 960 5 0.3
check "$work/fragments.png" 1280 960 8 0.3
check "$work/fragments_series.png" 1280 960 3 0.3

for script in figure_max_shear figure_cracks figure_fragments; do
  if render "$scripts/$script.py" "$work/missing.pvd" "$work/missing.png" 2> "$work/err.txt"; then
    echo "$script: rendering a missing file did not fail"; exit 1
  fi
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || { echo "$script: not one line:"; cat "$work/err.txt"; exit 1; }
  grep -q "missing.pvd" "$work/err.txt" || { echo "$script: error does not name the file"; exit 1; }
  [ ! -e "$work/missing.png" ] || { echo "$script: PNG written for a missing input"; exit 1; }
done
# A series that lists a missing frame: one line naming that frame (was: 22 lines of VTK errors
# and "has no disks"). A frame whose disk centres are all NaN: refused (was: a PNG, exit 0).
sed 's#file="[^"]*"#file="no_such_frame.vtu"#' "$frames/series.pvd" > "$work/missing_frame.pvd"
/usr/bin/python3 - "$frames/fractured.vtu" "$work/nan_points.vtu" <<'PY'
import sys
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter
r = vtkXMLUnstructuredGridReader(); r.SetFileName(sys.argv[1]); r.Update()
g = r.GetOutput(); p = g.GetPoints().GetData()
for k in range(p.GetNumberOfTuples()):
    p.SetTuple3(k, float("nan"), float("nan"), 0.0)
w = vtkXMLUnstructuredGridWriter(); w.SetFileName(sys.argv[2]); w.SetInputData(g); w.Write()
PY
for script in figure_max_shear figure_cracks figure_fragments; do
  for input in missing_frame.pvd nan_points.vtu; do
    rm -f "$work/bad.png"
    if render "$scripts/$script.py" "$work/$input" "$work/bad.png" 2> "$work/err.txt"; then
      echo "$script $input: did not fail"; exit 1
    fi
    [ "$(wc -l < "$work/err.txt")" -eq 1 ] || { echo "$script $input: not one line:"; cat "$work/err.txt"; exit 1; }
    [ ! -e "$work/bad.png" ] || { echo "$script $input: PNG written"; exit 1; }
  done
  grep -q "nan_points.vtu': the 'Points' array holds nan" "$work/err.txt" ||
    { echo "$script: wrong reason for NaN points:"; cat "$work/err.txt"; exit 1; }
done
render "$scripts/figure_cracks.py" "$work/missing_frame.pvd" "$work/bad.png" 2> "$work/err.txt" || true
grep -q "frame '.*no_such_frame.vtu' listed in '.*missing_frame.pvd' does not exist" "$work/err.txt" ||
  { echo "missing frame: wrong reason:"; cat "$work/err.txt"; exit 1; }
echo "figure test passed"

#!/usr/bin/env bash
# Case 4, the steel warhead into a concrete disc: runs the case files (default: 100, 50 and
# 25 m/s at full size, one after the other with 2 threads), then the numbers (analyse.py) and
# the figures (figures.py), all into one folder.
# Usage: cases/warhead/run_all.sh [OUTPUT_DIR] [CASE.toml ...]
#   OUTPUT_DIR  default out/warhead
#   CASE.toml   default cases/warhead/case.toml case_50.toml case_25.toml
# Environment: HEXDEM (the program; default build/release/solver/hexdem, else the first
# build/*/solver/hexdem), HEXDEM_PLUGIN (HexDEMFilters.so), THREADS (default 2).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:-out/warhead}
shift || true
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=("$here/case.toml" "$here/case_50.toml" "$here/case_25.toml")
threads=${THREADS:-2}

first_of() { for f in "$@"; do [ -e "$f" ] && { echo "$f"; return; }; done; }
hexdem=${HEXDEM:-$(first_of "$root/build/release/solver/hexdem" "$root"/build/*/solver/hexdem)}
[ -n "$hexdem" ] && [ -x "$hexdem" ] || { echo "run_all.sh: hexdem not built (scripts/build.sh release)" >&2; exit 2; }
build=$(cd "$(dirname "$hexdem")/.." && pwd)
plugin=${HEXDEM_PLUGIN:-$build/lib/paraview-5.11/plugins/HexDEMFilters/HexDEMFilters.so}
[ -f "$plugin" ] || { echo "run_all.sh: $plugin: no such file (HexDEMFilters plugin not built)" >&2; exit 2; }
export PYTHONPATH="$build/lib/python3.11/site-packages${PYTHONPATH:+:$PYTHONPATH}"

mkdir -p "$out"
out=$(cd "$out" && pwd)
series=()
warned=()  # runs that completed with a warning (hexdem run exit 3): analysed, then exit 3
: > "$out/warhead_wall_times.txt"
for c in "${cases[@]}"; do
  [ -f "$c" ] || { echo "run_all.sh: $c: no such case file" >&2; exit 2; }
  name=$(sed -n 's/^name = "\(.*\)"/\1/p' "$c" | head -n 1)
  echo "== $name ($c), $threads threads, load average $(cut -d' ' -f1-3 /proc/loadavg)"
  rc=0
  "$hexdem" run "$c" --out "$out" --threads "$threads" | tee "$out/$name.log" || rc=$?
  if [ "$rc" -eq 3 ]; then
    warned+=("$name")
  elif [ "$rc" -ne 0 ]; then
    echo "run_all.sh: $name: hexdem run failed (exit $rc)" >&2
    exit "$rc"
  fi
  echo "$name: $(grep -o 'wall [0-9.]* s' "$out/$name.log") with $threads threads" >> "$out/warhead_wall_times.txt"
  series+=("$out/$name.pvd")
done

/usr/bin/python3 "$here/analyse.py" "${series[@]}" --json "$out/warhead_summary.json" \
  --csv "$out/warhead_summary.csv"
HEXDEM_PLUGIN="$plugin" "$root/scripts/pvbatch-xvfb.sh" "$here/figures.py" "$out/warhead_summary.json" "$out"

cat <<MSG

Warhead case: everything is in $out
  series (ParaView):  $(cd "$out" && ls -1 warhead_*.pvd | tr '\n' ' ')
  histories (CSV):    <case>.bodies.csv (warhead and target: mass, centre, velocity, momentum,
                      kinetic energy), <case>.energy.csv (Eq. 25)
  numbers:            warhead_summary.csv, warhead_summary.json
  figures (PNG):      warhead_damage_forms.png, warhead_velocity.png, <case>_cracks_*.png,
                      <case>_fragments_end.png
  wall times:         warhead_wall_times.txt
$(sed 's/^/    /' "$out/warhead_wall_times.txt")
Open in ParaView:  paraview $out/${series[0]##*/}
  The points are the disk centres: representation "Point Gaussian", Scale Array "radius",
  Gaussian Radius 1, colour by "damage" or "velocity". The hexdem filters (crack map,
  fragments, max shear) need the plugin: Tools > Manage Plugins > Load New >
  $plugin
  (or start ParaView with PV_PLUGIN_PATH=$(dirname "$plugin")), then Filters > hexdem.
MSG
if [ ${#warned[@]} -gt 0 ]; then
  echo "run_all.sh: warning: ${warned[*]} completed with a warning (energy balance above [time] energy_warning; see $out/<case>.log): their numbers may be wrong" >&2
  exit 3
fi

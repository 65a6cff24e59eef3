#!/usr/bin/env bash
# Meshing benchmark: a 1,000,000-disk lattice inside a 1,000-vertex polygon with 10 holes,
# single-threaded. Reports the generation time (as `hexdem mesh` prints it), the whole
# command's wall time including the compressed .vtu, and the peak memory per disk.
# Usage: scripts/bench-mesh.sh [N_DISKS]   (after scripts/build.sh release)
set -euo pipefail
cd "$(dirname "$0")/.."
n=${1:-1000000}
hexdem=${HEXDEM:-build/release/solver/hexdem}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
/usr/bin/python3 scripts/make_bench_outline.py "$work/bench.toml" "$n"
/usr/bin/time -f "%e %M" -o "$work/time.txt" \
  "$hexdem" mesh "$work/bench.toml" -j 1 -o "$work/bench.vtu" | tee "$work/summary.txt"
read -r wall rss_kb < "$work/time.txt"
disks=$(awk '/disks/ {print $2; exit}' "$work/summary.txt")
gen=$(awk '/generation/ {print $3; exit}' "$work/summary.txt")
size=$(stat -c %s "$work/bench.vtu")
echo
echo "benchmark: disks $disks, generation ${gen} s, whole command ${wall} s," \
  "peak RSS $((rss_kb / 1024)) MiB = $(( rss_kb * 1024 / disks )) bytes/disk," \
  ".vtu $((size / 1024 / 1024)) MiB"

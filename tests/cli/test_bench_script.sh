#!/usr/bin/env bash
# scripts/bench-vs-lammps.sh end to end at a tiny size: its rounds and medians, and either the
# ratios against LAMMPS or the message that LAMMPS is absent. No speed is checked (speeds are
# measured and reported in docs/benchmarks.md, never asserted by tests).
# Usage: test_bench_script.sh HEXDEM SOURCE_DIR
set -euo pipefail
hexdem=$1
source_dir=$2
script="$source_dir/scripts/bench-vs-lammps.sh"

out=$(HEXDEM="$hexdem" "$script" --disks 2000 --steps 20 --threads 1 --rounds 2 2>&1)
echo "$out"
fail() { echo "FAILED: $1" >&2; exit 1; }
grep -Eq '^  rotation +1 thread\(s\): +[0-9.e+]+ [0-9.e+]+  median [0-9.e+]+$' <<< "$out" || fail "no rotation rounds and median"
grep -Eq '^  local-strain +1 thread\(s\): +[0-9.e+]+ [0-9.e+]+  median [0-9.e+]+$' <<< "$out" || fail "no local-strain rounds and median"
if grep -q "LAMMPS comparison skipped" <<< "$out"; then
  grep -q "apt-get install lammps" <<< "$out" || fail "the skip message does not say how to install LAMMPS"
else
  grep -Eq '^  rotation +1 thread\(s\): +[0-9.]+ [0-9.]+  median [0-9.]+$' <<< "$(sed -n '/^ratios/,$p' <<< "$out")" ||
    fail "no ratios against LAMMPS"
fi

# A bad --rounds is one line, exit 2.
set +e
err=$("$script" --rounds 0 2>&1 > /dev/null)
rc=$?
set -e
[ "$rc" = 2 ] || fail "--rounds 0 exited $rc, not 2"
[ "$(wc -l <<< "$err")" = 1 ] || fail "--rounds 0 printed more than one line: $err"
grep -q -- "--rounds must be a whole number >= 1, got '0'" <<< "$err" || fail "--rounds 0: $err"
echo "bench-vs-lammps.sh: OK"

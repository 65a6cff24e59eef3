#!/usr/bin/env bash
# Solver step benchmark against LAMMPS: `hexdem bench` at 100,000 disks (rotation and
# local-strain shear models, 1 and 2 threads, 1001 steps) and, if LAMMPS is installed, the same
# 2D hexagonal lattice as a LAMMPS bond network (atom_style bond, bond_style harmonic,
# ~100,000 atoms, 1001 steps, no output). Prints particle-steps/s of each run and the ratios
# hexdem / LAMMPS at the same thread count (docs/benchmarks.md, "Solver step: `hexdem bench`").
#
# Usage: scripts/bench-vs-lammps.sh [--install] [--disks N] [--steps S] [--threads "1 2"] [--rounds K]
#   (after scripts/build.sh release; HEXDEM=path overrides the binary, LMP=path the LAMMPS one)
#   --install  apt-get install lammps first if no LAMMPS binary is found (needs root)
#   --rounds K run every member K times, interleaved (round 1: each hexdem run and each LAMMPS
#              run once, then round 2, ...), and print each round's ratios and their median
#              (default 3). A shared or virtual machine's speed drifts by tens of % within
#              minutes; a ratio of two runs made minutes apart measures the drift as well.
#
# LAMMPS threads: with its OPENMP package, `-sf omp -pk omp T`; Debian's package is built
# without it, and then T MPI ranks (mpirun -np T) stand in for T threads (said in the output).
set -euo pipefail
cd "$(dirname "$0")/.."
hexdem=${HEXDEM:-build/release/solver/hexdem}
disks=100000
steps=1001
thread_counts="1 2"
rounds=3
install=0
while [ $# -gt 0 ]; do
  case "$1" in
    --install) install=1 ;;
    --disks) disks=$2; shift ;;
    --steps) steps=$2; shift ;;
    --threads) thread_counts=$2; shift ;;
    --rounds) rounds=$2; shift ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) echo "bench-vs-lammps.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
if ! [[ "$rounds" =~ ^[1-9][0-9]*$ ]]; then
  echo "bench-vs-lammps.sh: --rounds must be a whole number >= 1, got '$rounds'" >&2
  exit 2
fi
if [ ! -x "$hexdem" ]; then
  echo "bench-vs-lammps.sh: $hexdem not found: run scripts/build.sh release first" >&2
  exit 2
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Another busy process makes the multi-threaded runs meaningless: OpenMP threads and MPI ranks
# wait for each other at every pass, and one of them waiting for a core costs a scheduler
# slice. Say so rather than report such a figure as the program's.
read -r load1 _ < /proc/loadavg 2>/dev/null || load1=0
if awk -v l="$load1" 'BEGIN { exit !(l > 0.5) }'; then
  echo "bench-vs-lammps.sh: warning: load average $load1 before the runs: another process is using the CPU, and the" \
    "figures (above all the multi-threaded ones) will be too low" >&2
fi

# particle-steps/s of one `hexdem bench` run.
hexdem_run() {  # model threads
  echo "== hexdem bench --disks $disks --model $1 --steps $steps --threads $2 (round $round)" >&2
  "$hexdem" bench --disks "$disks" --model "$1" --steps "$steps" --threads "$2" > "$work/hexdem.txt"
  sed 's/^/  /' "$work/hexdem.txt" | grep -E 'step time|particle-steps' >&2
  awk -F': ' '/^particle-steps\/s:/ {print $2}' "$work/hexdem.txt"
}

find_lammps() {
  if [ -n "${LMP:-}" ]; then command -v "$LMP" && return 0; fi
  command -v lmp || command -v lmp_serial || command -v lmp_mpi || return 1
}
lmp=$(find_lammps || true)
if [ -z "$lmp" ] && [ "$install" = 1 ]; then
  echo "== installing LAMMPS (apt-get install -y lammps)"
  apt-get install -y lammps
  lmp=$(find_lammps || true)
fi

# The same lattice: `lattice hex` with nearest-neighbour spacing 1 (LJ units), a square block
# of cells of 2 atoms (1 x sqrt(3)), every nearest-neighbour pair a harmonic bond. The pair
# style only serves create_bonds (pair zero: no pair forces; bonded pairs are excluded from
# its neighbour list). Random velocities (seeded) load the bonds.
nx=$(awk -v n="$disks" 'BEGIN { printf "%d", sqrt(n / 2 * sqrt(3)) + 0.5 }')
ny=$(awk -v n="$disks" -v nx="$nx" 'BEGIN { printf "%d", n / 2 / nx + 0.5 }')
cat > "$work/in.hex" <<EOF
units lj
dimension 2
boundary s s p
atom_style bond
lattice hex 1.0
region block block 0 $nx 0 $ny -0.5 0.5
create_box 1 block bond/types 1 extra/bond/per/atom 6 extra/special/per/atom 40
create_atoms 1 box
mass 1 1.0
pair_style zero 1.2
pair_coeff * *
bond_style harmonic
bond_coeff 1 100.0 \$(xlat)
create_bonds many all all 1 0.9 1.2
comm_modify cutoff 3.0
velocity all create 0.01 12345 loop geom
fix 1 all nve
fix 2 all enforce2d
timestep 0.001
thermo 0
run $steps
EOF

omp=0
if [ -n "$lmp" ] && "$lmp" -h | sed -n '/Installed packages/,/List of/p' | grep -qw OPENMP; then omp=1; fi
if [ "$(id -u)" = 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi

# particle-steps/s of one LAMMPS run, empty if it cannot run at that thread count.
lammps_run() {  # threads
  local t=$1 how cmd omp_threads line
  if [ "$omp" = 1 ]; then
    how="$t OpenMP thread(s) (-sf omp -pk omp $t)"
    cmd=("$lmp" -sf omp -pk omp "$t" -in "$work/in.hex" -log none -screen "$work/lammps.txt")
  elif [ "$t" = 1 ]; then
    how="1 process"
    cmd=("$lmp" -in "$work/in.hex" -log none -screen "$work/lammps.txt")
  elif command -v mpirun > /dev/null; then
    how="$t MPI ranks (this LAMMPS has no OPENMP package)"
    cmd=(mpirun -np "$t" "$lmp" -in "$work/in.hex" -log none -screen "$work/lammps.txt")
  else
    echo "LAMMPS at $t threads skipped: no OPENMP package in $lmp and no mpirun" >&2
    return 0
  fi
  echo "== LAMMPS, bond_style harmonic, $how (round $round)" >&2
  # Threads only with the OPENMP package (LAMMPS counts ranks x OMP_NUM_THREADS as procs).
  omp_threads=1
  [ "$omp" = 1 ] && omp_threads=$t
  OMP_NUM_THREADS=$omp_threads "${cmd[@]}" > /dev/null
  # "Loop time of X on P procs for S steps with N atoms"
  line=$(grep '^Loop time of' "$work/lammps.txt")
  echo "  $line" >&2
  echo "$line" | awk '{ printf "%.6g\n", $12 * $9 / $4 }'
}

# The rounds: every member once per round, LAMMPS next to the hexdem runs it is compared with.
declare -A hexdem_rate lammps_rate
for round in $(seq 1 "$rounds"); do
  for t in $thread_counts; do
    for model in rotation local-strain; do
      hexdem_rate[$model,$t,$round]=$(hexdem_run "$model" "$t")
    done
    if [ -n "$lmp" ]; then lammps_rate[$t,$round]=$(lammps_run "$t"); fi
  done
done

median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print ""; else if (NR % 2) printf "%.4g", v[(NR + 1) / 2]; else printf "%.4g", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
rounds_of() {  # key prefix, array name: the values of the rounds, space-separated
  local -n arr=$2
  local r out=""
  for r in $(seq 1 "$rounds"); do out="$out ${arr[$1,$r]:-}"; done
  echo "$out"
}

echo
echo "hexdem particle-steps/s ($disks disks, $steps steps; rounds 1..$rounds, then the median):"
for model in rotation local-strain; do
  for t in $thread_counts; do
    v=$(rounds_of "$model,$t" hexdem_rate)
    printf '  %-12s %s thread(s): %s  median %s\n' "$model" "$t" "$v" "$(echo "$v" | median)"
  done
done
set -- $thread_counts
if [ $# -ge 2 ]; then
  t1=$1
  shift $(($# - 1))
  tn=$1
  echo "hexdem speed-up $tn / $t1 thread(s), each round's pair:"
  for model in rotation local-strain; do
    v=""
    for r in $(seq 1 "$rounds"); do
      v="$v $(awk -v a="${hexdem_rate[$model,$tn,$r]}" -v b="${hexdem_rate[$model,$t1,$r]}" 'BEGIN { printf "%.3f", a / b }')"
    done
    printf '  %-12s %s  median %s\n' "$model" "$v" "$(echo "$v" | median)"
  done
fi
if [ -z "$lmp" ]; then
  echo
  echo "LAMMPS comparison skipped: no lmp, lmp_serial or lmp_mpi on PATH."
  echo "Install it with 'apt-get install lammps' (Debian, Ubuntu), or run this script with --install."
  exit 0
fi
echo "LAMMPS particle-steps/s:"
for t in $thread_counts; do
  v=$(rounds_of "$t" lammps_rate)
  printf '  %s thread(s): %s  median %s\n' "$t" "$v" "$(echo "$v" | median)"
done

echo
echo "ratios hexdem / LAMMPS (particle-steps/s, same thread count, runs of the same round):"
for model in rotation local-strain; do
  for t in $thread_counts; do
    v=""
    for r in $(seq 1 "$rounds"); do
      [ -n "${lammps_rate[$t,$r]:-}" ] || continue
      v="$v $(awk -v h="${hexdem_rate[$model,$t,$r]}" -v l="${lammps_rate[$t,$r]}" 'BEGIN { printf "%.3f", h / l }')"
    done
    [ -n "$v" ] || continue
    printf '  %-12s %s thread(s): %s  median %s\n' "$model" "$t" "$v" "$(echo "$v" | median)"
  done
done

#!/usr/bin/env python3
"""Stability study (the paper's Fig. 8): the relative energy error Err(t) (Eq. 25) for several
time steps around the critical one, and the measured critical step (bisection on dt between a
stable and a blowing-up run) against the solver's estimate, the Bloch value and Eq. 24.

    python3 cases/stability/run_study.py HEXDEM OUT_DIR [--quick] [--check]

Writes OUT_DIR/stability_energy_error.png, OUT_DIR/stability.json and prints a summary.
--quick runs fewer cases and a coarser bisection (the ctest version). --check exits 1 unless the
measured critical step lies between 1.00 and 1.03 times the solver's (which must be safe but
not wasteful), the runs below it keep |Err| < 1e-6 and the runs above it blow up.
"""
import json
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def run(hexdem, out_dir, dt, end, tag):
    """Runs the case with time step dt; returns (ok, stdout, stderr, energy rows)."""
    with open(os.path.join(HERE, "case.toml")) as f:
        text = f.read()
    text = re.sub(r"(?m)^dt = .*$", "dt = %.17g" % dt, text)
    text = re.sub(r"(?m)^end = .*$", "end = %.17g" % end, text)
    text = text.replace('name = "stability"', 'name = "%s"' % tag)
    case = os.path.join(out_dir, tag + ".toml")
    with open(case, "w") as f:
        f.write(text.replace('outline', 'outline'))
    p = subprocess.run([hexdem, "run", case, "--out", out_dir], capture_output=True, text=True)
    # 0 and 3 (completed, with an energy warning) ran to the end; 4 stopped (blow-up).
    if p.returncode not in (0, 3, 4):
        sys.exit("run_study.py: hexdem failed: " + p.stderr.strip())
    rows = []
    with open(os.path.join(out_dir, tag + ".energy.csv")) as f:
        header = next(f).strip().split(",")
        t, e = header.index("time"), header.index("relative_error")
        for line in f:
            v = line.strip().split(",")
            rows.append((float(v[t]), float(v[e])))
    return p.returncode in (0, 3), p.stdout, p.stderr, rows


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    hexdem, out_dir = sys.argv[1], sys.argv[2]
    quick = "--quick" in sys.argv
    os.makedirs(out_dir, exist_ok=True)
    end = 100e-6
    # The solver's critical step estimates, from a first run's summary line.
    ok, out, err, _ = run(hexdem, out_dir, 1e-9, 1e-9, "probe")
    m = re.search(r"critical ([0-9.e+-]+) s: Bloch ([0-9.e+-]+) s, finite model ([0-9.e+-]+) s; Eq. 24 ([0-9.e+-]+) s", out)
    if not m:
        sys.exit("run_study.py: no time-step line in the output:\n" + out + err)
    dt_c, dt_bloch, dt_finite, dt_eq24 = (float(x) for x in m.groups())
    factors = [0.9, 1.1] if quick else [0.8, 0.95, 1.0, 1.01, 1.02, 1.05, 1.1, 1.5]
    curves = {}
    for f in factors:
        ok, out, err, rows = run(hexdem, out_dir, f * dt_c, end, "dt_%.3f" % f)
        blow = re.search(r"blow-up at step (\d+) \(t = ([0-9.e+-]+) s\)", err)
        curves[f] = dict(ok=ok, rows=rows, blow_up_time=float(blow.group(2)) if blow else None)
    # Bisection on the factor: stable means running to the end without a blow-up.
    lo, hi = 0.9, 1.1
    while hi - lo > (0.005 if quick else 0.002):
        mid = 0.5 * (lo + hi)
        ok, _, _, _ = run(hexdem, out_dir, mid * dt_c, end, "bisect")
        lo, hi = (mid, hi) if ok else (lo, mid)
    measured = 0.5 * (lo + hi) * dt_c
    result = dict(dt_critical_solver=dt_c, dt_bloch=dt_bloch, dt_finite_model=dt_finite,
                  dt_eq24=dt_eq24, dt_measured=measured, bracket=[lo * dt_c, hi * dt_c],
                  runs={"%.3f" % f: dict(stable=c["ok"], blow_up_time=c["blow_up_time"],
                                         max_abs_error=max((abs(e) for _, e in c["rows"]), default=None))
                        for f, c in curves.items()})
    with open(os.path.join(out_dir, "stability.json"), "w") as f:
        json.dump(result, f, indent=1)
    print("critical step: measured %.4g s (bracket %.4g-%.4g s); solver %.4g s (Bloch %.4g s, finite model %.4g s); Eq. 24 %.4g s"
          % (measured, lo * dt_c, hi * dt_c, dt_c, dt_bloch, dt_finite, dt_eq24))
    for f, c in curves.items():
        print("  dt = %.3f dt_c: %s" % (f, "stable, max |Err| %.2g" % result["runs"]["%.3f" % f]["max_abs_error"]
                                        if c["ok"] else "blow-up at t = %.3g s" % c["blow_up_time"]))
    if "--check" in sys.argv:
        ratio = measured / dt_c
        bad = [f for f, c in curves.items() if (f <= 1.0) != c["ok"]]
        worst = max((result["runs"]["%.3f" % f]["max_abs_error"] for f, c in curves.items() if c["ok"]), default=0)
        if not 1.0 <= ratio <= 1.03 or bad or worst > 1e-6:
            sys.exit("stability check failed: measured / solver critical step %.4f, unexpected runs %s, "
                     "largest stable |Err| %.2g" % (ratio, bad, worst))
        print("stability check passed: measured / solver critical step %.4f" % ratio)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for f, c in curves.items():
        t = [1e6 * r[0] for r in c["rows"] if r[0] > 0]
        e = [max(abs(r[1]), 1e-16) for r in c["rows"] if r[0] > 0]
        line, = ax.semilogy(t, e, label="dt = %.2f dt_c%s" % (f, "" if c["ok"] else " (blow-up)"))
        if not c["ok"]:  # the run stops when the energy exceeds ten times the input
            ax.semilogy([1e6 * c["blow_up_time"]], [10.0], "x", color=line.get_color(), markersize=9)
    ax.set_xlabel("t [us]")
    ax.set_ylabel("|relative energy error| (Eq. 25)")
    ax.set_ylim(1e-12, 1e2)
    ax.set_title("Energy error against time, material B, dt_c = %.1f ns" % (dt_c * 1e9))
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "stability_energy_error.png"), dpi=120)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Fictitious-crack reference of the Brazilian disc: an independent finite-element model.

    brazilian_fe.py [--h MM] [--json OUT.json] [--check] [--compare RUN.json ... [--tolerance PCT]]

The disc of cases/material_tests/brazilian.toml (D = 102.70 mm, flattened into two loading flats
of 21.35 mm at y = +-50.23 mm, t = 10 mm, plane stress, E 30 GPa, nu 0.2, f_t 3 MPa, G_F 100
J/m^2), computed with the fictitious crack of Hillerborg, Modeer and Petersson (1976): a linear
elastic continuum and one cohesive crack on the loaded diameter, closed until its stress
reaches f_t and then softening linearly, sigma = f_t (1 - w / w_c), w_c = 2 G_F / f_t (the law
of hexdem's `fracture_energy`). Nothing else in common with hexdem: no lattice, no dynamics, no
nonlocal averaging; a static solution.

A quarter of the disc is meshed (x <= 0, y >= 0): bilinear rectangles of side about h on a
grid, the rim a staircase of the elements whose centre lies inside the circle. Symmetry holds
y on y = 0 and x on the diameter's closed part; the crack's nodes are the diameter's, from the
centre to the flat, whose end node stays held (in compression; checked). Every node of the flat
moves down by the same displacement and is free in x, as the case's `top` strip (a velocity in
y only). The crack is advanced node by node with fictitious_crack.py's solver (Petersson's
method, an active set of cohesive, stress-free and pressed-shut nodes) from the centre, where
the tension is largest, towards the flat.

Printed: the splitting stress 2 P / (pi D t) at which the crack starts (the centre's stress
reaches f_t), where its cohesive zone reaches D/4 and 3D/8 from the centre (the middle half and
three quarters of the diameter), and whether the load rises all the way: with one cohesive
crack and an elastic rest, the disc carries more load after the crack has formed, so its
largest load is set by whatever else fails (in hexdem: the wedges under the flats), not by the
split. The checks (exit 1 with --check) are fictitious_crack.py's: the energy balance within 1 %
of the work, no node closing again, no closed node over f_t, the held end in compression.

--compare RUN.json ... reads `run_study.py brazilian --json` files and prints, per run, its
split strength (analyse.py: the largest load before the crack spans the middle half of the
loaded diameter) and its largest load against the reference's; with --check and --tolerance
PCT it fails when a run's split strength deviates from the reference's crack-initiation stress by
more than PCT %.

Exit 2 on bad arguments or unreadable files (one line naming the file or option and value).
"""
import argparse
import importlib.util
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fictitious_crack as fc  # noqa: E402  (the element, the crack's solver)

# The disc of brazilian.toml [mm, N, MPa].
RADIUS = 51.35                 # rim radius [mm]: hypot(10.676604165, 50.229473419)
FLAT_Y = 50.229473419          # height of the loading flats [mm]
FLAT_HALF = 10.676604165       # half width of a flat [mm]
THICKNESS = 10.0               # [mm]
E_MPA = 30e3
NU = 0.2
FT_MPA = 3.0
GF_N_MM = 0.1                  # 100 J/m^2


def fail(msg, code=2):
    print("brazilian_fe.py: " + msg, file=sys.stderr)
    sys.exit(code)


def build(h):
    """Mesh, stiffness and the condensed crack problem of the quarter disc, element side ~h [mm]."""
    ny = int(round(FLAT_Y / h))
    ys = np.linspace(0.0, FLAT_Y, ny + 1)
    n_flat = max(1, int(round(FLAT_HALF / h)))
    hx = FLAT_HALF / n_flat                  # the flat's edge is a grid line
    xs = np.arange(-int(math.ceil(RADIUS / hx)), 1) * hx   # x <= 0, ascending
    # The rectangles whose centre lies inside the rim.
    mesh = fc.grid_mesh(xs, ys, lambda x0, x1, y0, y1: (x0 + x1) ** 2 + (y0 + y1) ** 2 <= 4.0 * RADIUS * RADIUS)
    px, py = mesh[2], mesh[3]
    tol = 1e-6
    crack = np.where(np.abs(px) < tol)[0]    # the loaded diameter; its end under the flat is held
    crack = crack[np.argsort(py[crack])]
    flat = np.where((np.abs(py - FLAT_Y) < tol) & (px >= -FLAT_HALF - tol))[0]
    flat = flat[np.argsort(px[flat])]        # its edge first
    base = np.where(py < tol)[0]             # y = 0: the disc's other symmetry line
    return dict(fc.condense(mesh, THICKNESS, crack, flat, base, E_MPA, NU), h=h, ft=FT_MPA, gf=GF_N_MM,
                thickness=THICKNESS, strip_width=2.0 * FLAT_HALF)


def stress(load_n):
    """The splitting stress 2 P / (pi D t) of the whole disc's load P [MPa]."""
    return 2.0 * load_n / (math.pi * 2.0 * RADIUS * THICKNESS)


def read_runs(path):
    """The runs of a run_study.py --json file of Brazilian runs (exit 2 when it is not one)."""
    try:
        runs = json.load(open(path))["runs"]
        for r in runs:
            for key in ("split_strength_MPa", "peak_strength_MPa", "radius", "angle"):
                float(r[key])
    except (OSError, ValueError, KeyError, TypeError) as e:
        fail("%s: not a run_study.py --json file of Brazilian runs (%s: %s)" % (path, type(e).__name__, e))
    return runs


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--h", default="0.5", help="element side [mm], 0.1 to 5 (default 0.5)")
    ap.add_argument("--json", help="write the curve and the figures here")
    ap.add_argument("--check", action="store_true", help="exit 1 when a check fails")
    ap.add_argument("--compare", nargs="+", default=[], help="run_study.py --json files of hexdem Brazilian runs")
    ap.add_argument("--tolerance", help="with --check: fail when a compared run's split strength deviates from the "
                                        "reference's crack-initiation stress by more than this many per cent")
    a = ap.parse_args(argv)
    h = fc.number("--h", a.h, fail)
    if not 0.1 <= h <= 5.0:
        fail("--h: %r mm lies outside 0.1 to 5 mm" % a.h)
    tol_pct = fc.tolerance("--tolerance", a.tolerance, a.compare, fail)
    loaded = [(p, read_runs(p)) for p in a.compare]
    if importlib.util.find_spec("scipy") is None:
        fail("scipy is needed (Debian: apt-get install python3-scipy)")

    m = build(h)
    # Until the cohesive zone reaches the flat (the strip's displacement is far beyond any run's).
    points, checks = fc.trace(m, 1.0, False)
    pts = points[1:]
    tip = np.array([p["tip_mm"] for p in pts])
    sig = np.array([stress(p["load_N"]) for p in pts])
    at = {q: float(np.interp(q * 2.0 * RADIUS, tip, sig)) for q in (0.25, 0.375)}
    rising = bool(np.all(np.diff(sig) >= -1e-9 * sig.max()))
    print("fictitious crack of the Brazilian disc, h = %g mm: %d nodes, %d elements, %d crack nodes"
          % (h, m["nodes"], m["elements"], len(m["area"]) + 1))
    print("splitting stress 2P/(pi D t): %.3f MPa when the crack starts at the centre; %.3f MPa when its cohesive zone "
          "reaches D/4 = %.1f mm (the middle half of the diameter); %.3f MPa at 3D/8 = %.1f mm; load rising all the "
          "way: %s (%.2f MPa with the tip at %.1f mm, %.1f mm stress-free)"
          % (sig[0], at[0.25], 0.5 * RADIUS, at[0.375], 0.75 * RADIUS, "yes" if rising else "no", sig[-1], tip[-1],
             pts[-1]["free_mm"]))
    print("checks: energy balance %.2e of W (<= 1e-2), re-closing %.2e w_c (<= 1e-9), closed nodes over f_t by %.2e "
          "(<= 1e-6), end under the flat in compression: %s"
          % (checks["energy_balance"], checks["reclosing"], checks["closed_over_ft"],
             "no" if checks["top_in_tension"] else "yes"))
    failed = fc.failed_checks(checks, "node under the flat")
    if a.json:
        out = dict(h_mm=h, initiation_MPa=float(sig[0]), quarter_span_MPa=at[0.25], three_eighths_span_MPa=at[0.375],
                   load_rising=rising, checks=checks, failed=failed,
                   points=[dict(p, split_stress_MPa=stress(p["load_N"])) for p in points])
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)
    if loaded:
        print("hexdem runs against it (split strength: the largest load before the crack spans the middle half):")
        print("| run | angle [deg] | r [mm] | split strength [MPa] | / initiation | / cohesive zone at D/4 "
              "| largest load [MPa] |")
        print("|---|---|---|---|---|---|---|")
        for path, runs in loaded:
            for r in runs:
                ratio = r["split_strength_MPa"] / sig[0]
                print("| %s | %g | %g | %.3f | %.3f | %.3f | %.3f |"
                      % (os.path.basename(path), r["angle"], r["radius"] * 1e3, r["split_strength_MPa"], ratio,
                         r["split_strength_MPa"] / at[0.25], r["peak_strength_MPa"]))
                if tol_pct is not None and abs(ratio - 1.0) * 100.0 > tol_pct:
                    failed.append("the run at %g degrees, r = %g mm, splits %.1f %% off the crack-initiation stress "
                                  "(tolerance %g %%)" % (r["angle"], r["radius"] * 1e3, (ratio - 1.0) * 100.0, tol_pct))
    return fc.exit_code(failed, a.check)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

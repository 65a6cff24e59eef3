#!/usr/bin/env python3
"""Fictitious-crack reference of the notched beam: an independent finite-element model.

    fictitious_crack.py [--h MM] [--end MM] [--supports strip|point] [--strip bonded|contact]
                        [--json OUT.json] [--check]
                        [--compare RUN.json ... [--compare-until MM] [--work-tolerance PCT]]

The beam of cases/material_tests/notched_beam.toml (span 2 m, length 2.2 m, depth 200.918 mm,
notch 100 mm deep and 10 mm wide, t = 50 mm, plane stress, E 30 GPa, nu 0.2, f_t 3.33 MPa,
G_F 124 J/m^2, hinged supports, a 20 mm loading strip), computed with the fictitious crack model of
Hillerborg, Modeer and Petersson (1976), the model Petersson (1981) fitted his beam tests with:
a linear elastic continuum (bilinear quadrilaterals, 2 x 2 Gauss points) and one cohesive crack
on the symmetry line above the notch, closed until its stress reaches f_t and then softening
linearly, sigma = f_t (1 - w / w_c) with w_c = 2 G_F / f_t, so that a fully opened crack has
dissipated G_F per unit area. The same linear law as hexdem's `fracture_energy`
(docs/model.md, "Fracture energy and softening"), but nothing else in common: no lattice, no
dynamics, no disks; a static solution on a mesh of squares of side h.

By default the boundary conditions are the case's: the beam rests on one node at x = -1 m
(a hinge: the case's 0.2 mm support edges hold one disk each), every node of the 20 mm
loading strip at the same deflection, pushing or pulling. `--supports strip` holds every node of
a 20 mm strip at x = -1 m vertically instead, as the case's earlier builds did (which resists
the beam's rotation there); `--strip contact` lets the loading strip's nodes lift off (a plate
that only pushes).

Half of the beam is meshed (x <= 0). The crack's nodes are the symmetry line's nodes from the
notch tip to the top; the top node is held (it stays in compression; checked). The crack is
advanced node by node (Petersson's method): for a tip at node k, the nodes below it carry the
cohesive law (or nothing once w > w_c), the nodes above are closed, and the deflection is the
one at which the tip node's stress is f_t. With linear softening each step is a linear
problem in the crack's openings and the deflection, solved on the crack's degrees of freedom
after a static condensation of the rest (one sparse factorisation in all). The curve is the
load P (both halves) against the loading strip's deflection, the quantity the hexdem case
measures with its `load_point` probe.

Checks (exit 1 with --check when one fails): the energy balance W = U + D at every point
(external work by the trapezoid rule over the points, elastic energy by Clapeyron's theorem,
dissipation integrated from the cohesive law) within 1 % of W; no node closes again after it
opened (the law has no unloading branch here); no closed node (above the tip, or pressed shut
below it) carries more than f_t; the top node stays in compression.

--compare RUN.json ... reads `run_study.py --json` files of hexdem notched-beam runs and
prints, per run, the peak, the work up to --compare-until (default 1 mm) against the
reference's, and the mean and mean absolute load differences over 0..--compare-until; with
--check and --work-tolerance PCT it fails when a run's work deviates by more than PCT %.

Exit 2 on bad arguments or unreadable files (one line naming the file or option and value).
"""
import argparse
import importlib.util
import json
import math
import os
import sys

import numpy as np

# The beam of notched_beam.toml [mm, N, MPa] (SI where the name says so).
LENGTH_HALF = 1100.0      # half length [mm]
DEPTH = 200.917894        # [mm]
NOTCH_DEPTH = 100.0       # [mm]
NOTCH_HALF_WIDTH = 5.0    # [mm]
SUPPORT = (-1010.0, -990.0)  # support strip [mm]
LOAD_HALF = 10.0          # half of the 20 mm loading strip [mm]
THICKNESS = 50.0          # [mm]
E_MPA = 30e3
NU = 0.2
FT_MPA = 3.33
GF_N_MM = 0.124           # 124 J/m^2 = 0.124 N/mm


def fail(msg, code=2):
    print("fictitious_crack.py: " + msg, file=sys.stderr)
    sys.exit(code)


def q4_stiffness(a, b, t, e_mpa=E_MPA, nu=NU):
    """Plane-stress bilinear rectangle a x b [mm], thickness t [mm], Young's modulus e_mpa [MPa],
    Poisson's ratio nu: 8 x 8 [N/mm]."""
    d = e_mpa / (1.0 - nu * nu) * np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, 0.5 * (1.0 - nu)]])
    ke = np.zeros((8, 8))
    g = 1.0 / math.sqrt(3.0)
    xi_n = np.array([-1.0, 1.0, 1.0, -1.0])
    eta_n = np.array([-1.0, -1.0, 1.0, 1.0])
    for xi in (-g, g):
        for eta in (-g, g):
            dn_dxi = 0.25 * xi_n * (1.0 + eta_n * eta)
            dn_deta = 0.25 * eta_n * (1.0 + xi_n * xi)
            dn_dx = dn_dxi * 2.0 / a
            dn_dy = dn_deta * 2.0 / b
            bm = np.zeros((3, 8))
            bm[0, 0::2] = dn_dx
            bm[1, 1::2] = dn_dy
            bm[2, 0::2] = dn_dy
            bm[2, 1::2] = dn_dx
            ke += bm.T @ d @ bm * (a * b / 4.0) * t
    return ke


def grid_mesh(xs, ys, keep):
    """Bilinear rectangles on the grid xs x ys [mm] (ascending), those for which keep(x0, x1, y0,
    y1) holds; returns their nodes (renumbered from 0), sizes and the nodes' coordinates."""
    nx, ny = len(xs) - 1, len(ys) - 1
    nid = lambda ix, iy: iy * (nx + 1) + ix  # noqa: E731
    elems = []
    sizes = []
    for iy in range(ny):
        for ix in range(nx):
            if not keep(xs[ix], xs[ix + 1], ys[iy], ys[iy + 1]):
                continue
            elems.append((nid(ix, iy), nid(ix + 1, iy), nid(ix + 1, iy + 1), nid(ix, iy + 1)))
            sizes.append((xs[ix + 1] - xs[ix], ys[iy + 1] - ys[iy]))
    elems = np.array(elems)
    used = np.unique(elems)
    renum = -np.ones((nx + 1) * (ny + 1), dtype=int)
    renum[used] = np.arange(len(used))
    return renum[elems], sizes, xs[used % (nx + 1)], ys[used // (nx + 1)]


def condense(mesh, thickness, crack, strip, held_y, e_mpa=E_MPA, nu=NU):
    """The crack problem on a grid_mesh: the stiffness condensed onto the x of the crack's nodes
    (crack, ordered along the crack; its last node's x is held) and the y of the strip's nodes,
    with the y of held_y held. Returns the model dict of trace() without the material."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    elems, sizes, px, py = mesh
    nn = len(px)
    rows, cols, vals = [], [], []
    cache = {}
    for e, (a, b) in zip(elems, sizes):
        key = (round(a, 9), round(b, 9))
        if key not in cache:
            cache[key] = q4_stiffness(a, b, thickness, e_mpa, nu)
        dofs = np.empty(8, dtype=int)
        dofs[0::2] = 2 * e
        dofs[1::2] = 2 * e + 1
        rows.append(np.repeat(dofs, 8))
        cols.append(np.tile(dofs, 8))
        vals.append(cache[key].ravel())
    k = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(2 * nn, 2 * nn))
    top = crack[-1]
    crack_free = crack[:-1]                      # the end node's x is held
    bdofs = np.concatenate([2 * crack_free, 2 * strip + 1])   # the condensed degrees of freedom
    fixed = np.concatenate([2 * held_y + 1, [2 * top]])
    special = np.zeros(2 * nn, dtype=bool)
    special[bdofs] = special[fixed] = True
    i = np.where(~special)[0]
    # Static condensation onto the crack's x and the strip's y: S = K_BB - K_Bi K_ii^-1 K_iB.
    kib = k[i][:, bdofs].toarray()
    x = spla.splu(k[i][:, i].tocsc()).solve(kib)
    s = k[bdofs][:, bdofs].toarray() - k[bdofs][:, i] @ x
    # The end node's x force (held by symmetry; it must stay in compression).
    top_row = k[2 * top][:, bdofs].toarray().ravel() - np.asarray(k[2 * top][:, i] @ x).ravel()
    gaps = np.diff(py[crack])
    area = np.zeros(len(crack_free))      # tributary area [mm^2]
    area += 0.5 * gaps * thickness
    area[1:] += 0.5 * gaps[:-1] * thickness
    return dict(s=s, top_row=top_row, y=py[crack_free], area=area, strip_x=px[strip], nodes=nn,
                elements=len(elems))


def number(option, text, fail_with):
    """An option's value as a float; fail_with(message) when it is not a number."""
    try:
        return float(text)
    except ValueError:
        fail_with("%s: not a number: %r" % (option, text))


def tolerance(option, text, compare, fail_with):
    """A --...-tolerance option [%]: None when absent; fail_with(message) unless it is a positive
    number given with --compare files."""
    if text is None:
        return None
    value = number(option, text, fail_with)
    if not value > 0 or not compare:
        fail_with("%s: needs a positive number and --compare files: %r" % (option, text))
    return value


def exit_code(failed, check):
    """Prints the failed checks on stderr; 1 if there are any and check is set, else 0."""
    if failed:
        print("check failed: " + "; ".join(failed), file=sys.stderr)
    return 1 if failed and check else 0


def failed_checks(checks, end_name):
    """The names of trace()'s checks that fail (end_name: the held end node)."""
    failed = []
    if checks["energy_balance"] > 1e-2:
        failed.append("energy balance")
    if checks["reclosing"] > 1e-9:
        failed.append("a node closed again")
    if checks["closed_over_ft"] > 1e-6:
        failed.append("a closed node carries more than f_t")
    if checks["top_in_tension"]:
        failed.append("the held %s is in tension" % end_name)
    return failed


def build(h, point_supports=False):
    """Mesh, stiffness and the condensed crack problem for element side h [mm].

    point_supports: the beam rests on one node at x = -1000 mm (a hinge, as the case) instead of
    a 20 mm strip, every node of which is held vertically (which resists the beam's rotation)."""
    nx = int(round(LENGTH_HALF / h))
    n1 = int(round(NOTCH_DEPTH / h))
    n2 = int(round((DEPTH - NOTCH_DEPTH) / h))
    xs = np.linspace(-LENGTH_HALF, 0.0, nx + 1)
    ys = np.concatenate([np.linspace(0.0, NOTCH_DEPTH, n1 + 1), np.linspace(NOTCH_DEPTH, DEPTH, n2 + 1)[1:]])
    # Every rectangle but those inside the notch.
    mesh = grid_mesh(xs, ys, lambda x0, x1, y0, y1: not (x0 >= -NOTCH_HALF_WIDTH - 1e-9 and y1 <= NOTCH_DEPTH + 1e-9))
    px, py = mesh[2], mesh[3]
    tol = 1e-6
    crack = np.where((np.abs(px) < tol) & (py >= NOTCH_DEPTH - tol))[0]
    crack = crack[np.argsort(py[crack])]
    lo, hi = (0.5 * (SUPPORT[0] + SUPPORT[1]),) * 2 if point_supports else SUPPORT
    support = np.where((py < tol) & (px >= lo - tol) & (px <= hi + tol))[0]
    load = np.where((np.abs(py - DEPTH) < tol) & (px >= -LOAD_HALF - tol))[0]
    return dict(condense(mesh, THICKNESS, crack, load, support), h=h, ft=FT_MPA, gf=GF_N_MM, thickness=THICKNESS,
                strip_width=2.0 * LOAD_HALF)


def trace(m, end_mm, contact):
    """The crack advanced node by node; returns the curve and the checks.

    m is a condensed model (build, or brazilian_fe.py's): the crack's nodes on the symmetry line
    x = 0 of a mesh on x <= 0 ("y", their tributary "area" [mm^2], the condensed stiffness "s"
    over their x and the strip's y degrees of freedom, "top_row" of the held end node), the
    strip's nodes ("strip_x"), and the material and section ("ft" [MPa], "gf" [N/mm],
    "thickness" [mm], "strip_width" [mm]).

    contact = False: the loading strip is bonded (every strip node at -delta, pulling or
    pushing, as hexdem's velocity condition on the `load` set); True: it only pushes (a node
    whose force would pull lifts off, a lifted node below the strip is pressed again).
    """
    ft, gf, thickness = m["ft"], m["gf"], m["thickness"]
    wc = 2.0 * gf / ft                    # [mm]
    s, area = m["s"], m["area"]
    n = len(area)
    ns = len(m["strip_x"])
    kco = 2.0 * area * ft / wc            # cohesive stiffness per node (opening = -2 u)
    points = [dict(deflection_mm=0.0, load_N=0.0, elastic_J=0.0, dissipated_J=0.0, tip_mm=float(m["y"][0]),
                   strip_contact_mm=m["strip_width"], cracked_mm=0.0, free_mm=0.0)]
    # Every crack node below the tip is cohesive (softening, 0 <= w <= w_c), free (w > w_c, no
    # traction) or shut (pressed closed, u = 0, its stress <= f_t); every strip node is pressed
    # (u = -delta) or lifted (no force, above the strip). An active set, iterated until every
    # node meets its state's conditions.
    COH, FREE, SHUT = 0, 1, 2
    state = np.full(n, SHUT)
    w_prev = np.zeros(n)
    checks = dict(reclosing=0.0, closed_over_ft=0.0, top_in_tension=False, snap_back=False, active_set_iterations=0)
    def solve(tip, state, pressed):
        """The crack's active set for a given strip contact; returns the solution or None."""
        state = state.copy()
        for it in range(500):
            unk = [j for j in range(tip) if state[j] != SHUT] + [n + q for q in range(ns) if not pressed[q]]
            rows = unk + [tip]
            dcol = -s[:, n + np.where(pressed)[0]].sum(axis=1)   # force per unit deflection
            a = np.zeros((len(rows), len(unk) + 1))
            a[:, :-1] = s[np.ix_(rows, unk)]
            a[:, -1] = dcol[rows]
            rhs = np.zeros(len(rows))
            for q, j in enumerate(unk):
                if j < n and state[j] == COH:
                    a[q, q] -= kco[j]
                    rhs[q] = area[j] * ft
            rhs[-1] = area[tip] * ft
            z = np.linalg.solve(a, rhs)
            delta = z[-1]
            ub = np.zeros(n + ns)
            ub[n + np.where(pressed)[0]] = -delta
            ub[unk] = z[:-1]
            w = -2.0 * ub[:n]
            f = s @ ub                    # force on the body at every condensed node [N]
            changed = False
            for j in range(tip):
                if state[j] == COH and w[j] < 0.0:
                    state[j] = SHUT
                    changed = True
                elif state[j] == COH and w[j] > wc:
                    state[j] = FREE
                    changed = True
                elif state[j] == SHUT and f[j] > area[j] * ft * (1.0 + 1e-12):
                    state[j] = COH
                    changed = True
            if not changed:
                return dict(state=state, delta=delta, ub=ub, f=f, w=w, iterations=it + 1)
        fail("the active set of the crack's nodes did not settle at tip %d" % tip, 1)

    def strip_ok(sol, pressed):
        f, ub, delta = sol["f"][n:], sol["ub"][n:], sol["delta"]
        pull = float(np.max(np.where(pressed, f, 0.0)))
        below = float(np.max(np.where(pressed, 0.0, -delta - ub)))
        return pull <= 1e-9 * float(np.abs(f).max()) and below <= 1e-9 * abs(delta)

    # Candidate contact sets of the strip (contact mode): the last step's first, then every
    # run of nodes from the strip's edge inwards and from its centre outwards (a flat strip on
    # a bent or hinged top touches either at its edges or at the centre), then all of them.
    candidates = []
    for k in range(1, ns + 1):
        candidates.append(np.arange(ns) < k)          # the strip's nodes are ordered by x: edge first
        candidates.append(np.arange(ns) >= ns - k)
    pressed = np.ones(ns, dtype=bool)
    tip = 0
    while tip < n:
        sol = solve(tip, state, pressed)
        if contact and not strip_ok(sol, pressed):
            for cand in candidates:
                sol = solve(tip, state, cand)
                if strip_ok(sol, cand):
                    pressed = cand
                    break
            else:
                fail("no contact set of the loading strip is in equilibrium at tip %d" % tip, 1)
        state, delta, ub, f, w = sol["state"], sol["delta"], sol["ub"], sol["f"], sol["w"]
        r = f[:n]
        checks["active_set_iterations"] = max(checks["active_set_iterations"], sol["iterations"])
        # A closed node above the tip over f_t: the crack reaches it first (at the notch's face
        # the largest stress is a node or two above the face). The tip moves there, and the
        # nodes passed over stay shut unless the active set opens them.
        ratio = r / (area * ft)
        above = np.arange(tip + 1, n)
        if len(above) and ratio[above].max() > 1.0 + 1e-9:
            tip = int(above[np.argmax(ratio[above])])
            continue
        free = state == FREE
        closed = np.array([j for j in range(n) if j > tip or state[j] == SHUT], dtype=int)
        if len(closed):
            checks["closed_over_ft"] = max(checks["closed_over_ft"], float(np.max(r[closed] / area[closed])) / ft - 1.0)
        if float(m["top_row"] @ ub) > 0.0:
            checks["top_in_tension"] = True
        checks["reclosing"] = max(checks["reclosing"], float(np.max(w_prev - w)) / wc)
        w_prev = w
        p_half = -float(f[n:][pressed].sum())
        u_half = 0.5 * float(f @ ub)                              # Clapeyron [N mm]
        coh = (np.arange(n) < tip) & (state == COH)
        g = np.where(free, gf, ft * (w - w * w / (2.0 * wc))) * area
        g = np.where(coh | free, g, 0.0)
        xs = m["strip_x"][pressed]
        points.append(dict(deflection_mm=delta, load_N=2.0 * p_half, elastic_J=2.0 * u_half * 1e-3,
                           dissipated_J=float(g.sum()) * 1e-3, tip_mm=float(m["y"][tip]),
                           strip_contact_mm=2.0 * float(-xs.min()) if len(xs) else 0.0,
                           # crack lengths: opened (w > 0) and stress-free (w >= w_c) [mm]
                           cracked_mm=float(np.sum(area[coh | free])) / thickness,
                           free_mm=float(np.sum(area[free])) / thickness))
        if delta < points[-2]["deflection_mm"]:
            checks["snap_back"] = True
        if delta > end_mm:
            break
        state[tip] = COH
        tip += 1
    # External work by the trapezoid rule, and the balance at every point.
    work = 0.0
    worst = 0.0
    for p0, p1 in zip(points, points[1:]):
        work += 0.5 * (p0["load_N"] + p1["load_N"]) * (p1["deflection_mm"] - p0["deflection_mm"]) * 1e-3
        p1["work_J"] = work
        if work > 0 and p1["deflection_mm"] <= end_mm:
            worst = max(worst, abs(work - p1["elastic_J"] - p1["dissipated_J"]) / work)
    points[0]["work_J"] = 0.0
    checks["energy_balance"] = worst
    return points, checks


def work_until(defl, load, x_end):
    """Trapezoid integral of load over deflection from 0 to x_end [N mm]."""
    keep = defl <= x_end
    x = np.append(defl[keep], x_end)
    y = np.append(load[keep], np.interp(x_end, defl, load))
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


def read_runs(path):
    """The runs of a run_study.py --json file of notched-beam runs (exit 2 when it is not one)."""
    try:
        runs = json.load(open(path))["runs"]
        for r in runs:
            for key in ("peak_load_N", "radius", "deflection_at_peak_mm"):
                float(r[key])
            if len(r["curve"]["deflection_mm"]) != len(r["curve"]["load_N"]):
                raise ValueError("the curve's columns differ in length")
    except (OSError, ValueError, KeyError, TypeError) as e:
        fail("%s: not a run_study.py --json file of notched-beam runs (%s: %s)" % (path, type(e).__name__, e))
    return runs


def compare(points, paths, x_end):
    """Per hexdem run: peak, work up to x_end and the load differences over 0..x_end.

    Returns the work ratios (hexdem / reference), one per run."""
    peak = max((p for p in points if p["deflection_mm"] <= x_end), key=lambda p: p["load_N"])
    ref_d = np.array([p["deflection_mm"] for p in points])
    ref_p = np.array([p["load_N"] for p in points])
    ref_w = work_until(ref_d, ref_p, x_end)
    print("hexdem runs against the fictitious-crack curve (peak %.0f N at %.3f mm; work to %.2f mm %.3f J):"
          % (peak["load_N"], peak["deflection_mm"], x_end, ref_w * 1e-3))
    print("| run | r [mm] | peak [N] | peak / reference | deflection at the peak [mm] | work to %.2f mm / reference "
          "| mean load difference [N] | mean absolute difference [N] |" % x_end)
    print("|---|---|---|---|---|---|---|---|")
    ratios = []
    for path, runs in paths:
        for r in runs:
            c = r["curve"]
            d = np.array(c["deflection_mm"])
            load = np.array(c["load_N"])
            if len(d) < 2 or d.max() < x_end:
                fail("%s: the run at r = %g m ends at %.3f mm, before %.2f mm" % (path, r["radius"], d.max(), x_end))
            keep = (d > 0) & (d <= x_end)
            diff = load[keep] - np.interp(d[keep], ref_d, ref_p)
            ratios.append(work_until(d, load, x_end) / ref_w)
            print("| %s | %g | %.0f | %.3f | %.3f | %.3f | %+.0f | %.0f |"
                  % (os.path.basename(path), r["radius"] * 1e3, r["peak_load_N"], r["peak_load_N"] / peak["load_N"],
                     r["deflection_at_peak_mm"], work_until(d, load, x_end) / ref_w, float(np.mean(diff)),
                     float(np.mean(np.abs(diff)))))
    return ratios


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--h", default="2.5", help="element side [mm]; 5 / h must be a whole number (default 2.5)")
    ap.add_argument("--end", default="2.0", help="last deflection [mm] (default 2, the hexdem case's end)")
    ap.add_argument("--work-tolerance", help="with --check: fail when a compared run's work up to --compare-until "
                                             "deviates from the reference's by more than this many per cent")
    ap.add_argument("--strip", default="bonded",
                    help="loading strip: 'bonded' (pushes and pulls, as the hexdem case's velocity condition; "
                         "default) or 'contact' (only pushes, as a loading plate)")
    ap.add_argument("--supports", default="point",
                    help="'point' (one node at x = +-1 m: a hinge, as the case's supports; default) or 'strip' "
                         "(20 mm strips, every node held vertically, as the case's earlier builds)")
    ap.add_argument("--json", help="write the curve and the figures here")
    ap.add_argument("--check", action="store_true", help="exit 1 when a check fails")
    ap.add_argument("--compare", nargs="+", default=[], help="run_study.py --json files of hexdem beam runs")
    ap.add_argument("--compare-until", default="1.0",
                    help="compare the curves from 0 to this deflection [mm] (default 1, before the crack nears the "
                         "loading strip)")
    a = ap.parse_args(argv)
    h = number("--h", a.h, fail)
    if not (h > 0 and abs(5.0 / h - round(5.0 / h)) < 1e-9 and 5.0 / h <= 64):
        fail("--h: %r mm does not divide the notch's half width of 5 mm (use 5, 2.5, 1.25 or 0.625)" % a.h)
    end = number("--end", a.end, fail)
    if not end > 0:
        fail("--end: must be positive: %r" % a.end)
    tol_pct = tolerance("--work-tolerance", a.work_tolerance, a.compare, fail)
    if a.supports not in ("strip", "point"):
        fail("--supports: %r is neither 'strip' nor 'point'" % a.supports)
    if a.strip not in ("bonded", "contact"):
        fail("--strip: %r is neither 'bonded' nor 'contact'" % a.strip)
    until = number("--compare-until", a.compare_until, fail)
    if not 0 < until <= end:
        fail("--compare-until: must lie in (0, --end]: %r" % a.compare_until)
    loaded = [(p, read_runs(p)) for p in a.compare]
    if importlib.util.find_spec("scipy") is None:
        fail("scipy is needed (Debian: apt-get install python3-scipy)")

    m = build(h, a.supports == "point")
    points, checks = trace(m, end, a.strip == "contact")
    # The peak over the deflections up to --end (the last point lies beyond it).
    peak = max((p for p in points if p["deflection_mm"] <= end), key=lambda p: p["load_N"])
    lig_m2 = (DEPTH - NOTCH_DEPTH) * THICKNESS * 1e-6
    # The figures at the end deflection, interpolated between the two points around it.
    dd = np.array([p["deflection_mm"] for p in points])
    last = {key: float(np.interp(end, dd, [p[key] for p in points]))
            for key in ("deflection_mm", "load_N", "work_J", "elastic_J", "dissipated_J", "tip_mm", "cracked_mm",
                        "free_mm")}
    print("fictitious crack, h = %g mm, %s loading strip, %s supports: %d nodes, %d elements, %d crack nodes"
          % (h, a.strip, "20 mm strip" if a.supports == "strip" else "point", m["nodes"], m["elements"], len(m["area"]) + 1))
    print("peak load %.1f N at %.3f mm (tip at %.1f mm)" % (peak["load_N"], peak["deflection_mm"], peak["tip_mm"]))
    print("at %.3f mm: load %.1f N (%.1f %% of the peak), tip at %.1f mm, W %.4f J, W / A_lig %.1f J/m^2, "
          "dissipated / A_lig %.1f J/m^2, elastic %.4f J; crack opened over %.1f mm, stress-free over %.1f mm"
          % (last["deflection_mm"], last["load_N"], 100.0 * last["load_N"] / peak["load_N"], last["tip_mm"],
             last["work_J"], last["work_J"] / lig_m2, last["dissipated_J"] / lig_m2, last["elastic_J"],
             last["cracked_mm"], last["free_mm"]))
    print("checks: energy balance %.2e of W (<= 1e-2), re-closing %.2e w_c (<= 1e-9), closed nodes over f_t by %.2e "
          "(<= 1e-6), top in compression: %s, snap-back: %s"
          % (checks["energy_balance"], checks["reclosing"], checks["closed_over_ft"],
             "no" if checks["top_in_tension"] else "yes", "yes" if checks["snap_back"] else "no"))
    failed = failed_checks(checks, "top node")
    if a.json:
        out = dict(h_mm=h, strip=a.strip, supports=a.supports, peak_load_N=peak["load_N"], deflection_at_peak_mm=peak["deflection_mm"],
                   work_of_fracture_J_m2=last["work_J"] / lig_m2, dissipated_over_ligament_J_m2=last["dissipated_J"] / lig_m2,
                   end_mm=end, checks=checks, failed=failed,
                   points=[p for p in points if p["deflection_mm"] < end] + [last])
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)
    if a.compare:
        for ratio in compare(points, loaded, until):
            if tol_pct is not None and abs(ratio - 1.0) * 100.0 > tol_pct:
                failed.append("a run's work up to %.2f mm is %.1f %% off the reference's (tolerance %g %%)"
                              % (until, (ratio - 1.0) * 100.0, tol_pct))
    return exit_code(failed, a.check)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

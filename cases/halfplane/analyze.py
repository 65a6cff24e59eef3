#!/usr/bin/env python3
"""Analysis of the half-plane cases from their probe histories, against the exact continuum
solution of halfplane_reference.py (independent of the solver).

    python3 analyze.py fronts CASE.toml OUT_DIR [--check TOL] [--json FILE] [--plot FILE] [--coarse]
    python3 analyze.py lamb   CASE.toml OUT_DIR [--check BOUND] [--json FILE] [--plot FILE] [--coarse]
    python3 analyze.py blowup CASE.toml OUT_DIR [--json FILE]

CASE.toml is the case that was run (fronts.toml, lamb.toml or a variant with another
[mesh] radius), OUT_DIR the --out folder of `hexdem run`. Material, load, lattice radius and
probe points are read from the case file; a probe records the disk nearest to its point,
which is placed here by the lattice rule of docs/lattice-generator.md (origin 0, angle 0).

fronts: front speeds of the qP wave along the surface (x) and into depth (y), of the qS wave
along the ray 70 degrees below the surface and of the Rayleigh wave, each from the slope of
arrival time against the predicted front time over the stations (see README.md). Printed for
the lattice and, with the same measure, for the continuum solution, against the theoretical
speeds. --check TOL exits 1 unless every lattice speed from the time shift is within TOL
(fraction) of theory.

lamb: surface displacement and velocity histories against the continuum solution (Lamb's
problem for the strip load): RMS difference over the run, divided by the peak of the
continuum history. --check BOUND exits 1 unless the vertical velocity error at every station
is below BOUND.

blowup: for rotation_unstable.toml, the time of the last good frame and the e-folding time of
the growing mode, from the energy rows (compare with the Bloch analysis, physics.md section 4).

--coarse evaluates the continuum solution on a coarser grid (0.5 us, 1 mm instead of 0.25 us,
0.5 mm), four times faster; enough for the r = 1 mm lattice of the ctest versions.

Units: SI. Needs numpy (matplotlib for --plot); Python >= 3.11 (tomllib).
"""
import json
import math
import os
import sys
import tomllib

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from run_status import require_completed  # noqa: E402
import halfplane_reference as ref  # noqa: E402

W = 0.25  # m: width and depth of the half model (outline.toml)


def fail(msg):
    sys.exit("analyze.py: " + msg)


def read_case(path):
    """Material constants, load parameters, lattice radius and probe points of a case file."""
    try:
        with open(path, "rb") as f:
            case = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        fail("%s: %s" % (path, e))
    mat = case["material"][0]
    rho = float(mat["density"])
    if "E" in mat:
        c = ref.isotropic_plane_stress(float(mat["E"]), float(mat["nu"]))
    else:
        c = tuple(float(mat[k]) for k in ("c11", "c12", "c22", "c66"))
    if case["case"].get("geometry") != "plane-stress":
        fail("%s: case.geometry: the reference is for plane stress (got %r)" % (path, case["case"].get("geometry")))
    load = case["load"][0]
    fn = load["function"]
    radius = case.get("mesh", {}).get("radius")
    if radius is None:
        outline = os.path.join(os.path.dirname(os.path.abspath(path)), case["mesh"]["outline"])
        with open(outline, "rb") as f:
            o = tomllib.load(f)
        radius = float(o["lattice"]["radius"]) * {"mm": 1e-3, "m": 1.0}[o.get("units", "m")]
    probes = [(p["name"], float(p["point"][0]), float(p["point"][1])) for p in case.get("probe", [])]
    return dict(name=case["case"].get("name", os.path.splitext(os.path.basename(path))[0]),
                c=c, rho=rho, p0=float(load["p0"]), alpha=float(fn["alpha"]), beta=float(fn["beta"]),
                a=0.02, radius=float(radius), probes=probes, end=float(case["time"]["end"]))


def lattice_site(x, y, r):
    """The lattice point nearest to (x, y): X = i 2r + (j odd ? r : 0), Y = j sqrt(3) r."""
    h = math.sqrt(3.0) * r
    best = None
    for j in (math.floor(y / h), math.ceil(y / h)):
        off = r if j % 2 else 0.0
        for i in (math.floor((x - off) / (2 * r)), math.ceil((x - off) / (2 * r))):
            X, Y = i * 2 * r + off, j * h
            dd = (X - x) ** 2 + (Y - y) ** 2
            if best is None or dd < best[0] - 1e-18:
                best = (dd, X, Y)
    return best[1], best[2]


def read_probes(case, out_dir):
    if not case["probes"]:
        fail("case '%s' has no [[probe]]" % case["name"])
    name = case["name"]
    path = os.path.join(out_dir, name + ".probes.csv")
    require_completed(path)
    try:
        d = np.genfromtxt(path, delimiter=",", names=True, deletechars="")
    except OSError as e:
        fail("%s: %s (run the case first)" % (path, e))
    return d


def group_velocity(c, rho, wave):
    """Group (ray) speed of the qP or qS wave as a function of the ray angle from the x axis."""
    c11, c12, c22, c66 = c
    phi = np.linspace(0.0, np.pi / 2, 20001)
    n1, n2 = np.cos(phi), np.sin(phi)
    g11 = c11 * n1 * n1 + c66 * n2 * n2
    g22 = c66 * n1 * n1 + c22 * n2 * n2
    g12 = (c12 + c66) * n1 * n2
    tr, det = g11 + g22, g11 * g22 - g12 * g12
    disc = np.sqrt(np.maximum(tr * tr / 4 - det, 0))
    v = np.sqrt(((tr / 2 + disc) if wave == "qP" else (tr / 2 - disc)) / rho)
    dv = np.gradient(v, phi)
    gx, gy = v * n1 - dv * n2, v * n2 + dv * n1
    ang = np.arctan2(gy, gx)
    if np.any(np.diff(ang) <= 0):
        fail("the %s wave surface has a cusp: group velocity is not single-valued" % wave)
    speed = np.hypot(gx, gy)
    return lambda psi: np.interp(np.abs(psi), ang, speed)


def front_time(px, py, a, speed_of_angle, n=401):
    """Earliest arrival at (px, py) of a front leaving every point of the strip |s| < a at t = 0
    with the ray speed speed_of_angle(angle from the surface)."""
    s = np.linspace(-a, a, n)
    dx, dy = px - s, -py
    return float(np.min(np.hypot(dx, dy) / speed_of_angle(np.arctan2(dy, np.abs(dx)))))


def front_curves(c, rho, a, t, n=181):
    """Predicted wave fronts at time t [s] of the strip |x| < a loaded from t = 0, for x >= 0:
    dict of polylines [(x, y), ...] [m] for the qP and qS fronts (every point of the strip
    emits the wave surface V(psi) t), the von Schmidt head wave (the line from the qP front on
    the surface tangent to the qS front) and the Rayleigh pulse on the surface (from
    c_R t - a to c_R t + a)."""
    curves = {}
    psi = np.linspace(0.0, np.pi / 2, n)
    for wave in ("qP", "qS"):
        v = group_velocity(c, rho, wave)(psi) * t
        pts = [(a + vi * math.cos(p), -vi * math.sin(p)) for vi, p in zip(v, psi)]
        curves[wave] = pts + [(0.0, pts[-1][1])]
    # Head wave: tangent to the qS front where its phase direction has the surface qP's
    # horizontal slowness, i.e. where its normal makes the same angle with the surface.
    x_p = a + float(group_velocity(c, rho, "qP")(0.0)) * t
    pts = np.array(curves["qS"][:-1])
    # The tangent point is where the line from (x_p, 0) touches the convex qS front: the
    # smallest angle of that line with the surface.
    ang = np.arctan2(-pts[:, 1], x_p - pts[:, 0])
    i = int(np.argmax(ang))
    curves["head"] = [(x_p, 0.0), (float(pts[i, 0]), float(pts[i, 1]))]
    c_r = ref.rayleigh_speed(c, rho)
    curves["rayleigh"] = [(max(c_r * t - a, 0.0), 0.0), (c_r * t + a, 0.0)]
    return curves


def reflection_time(px, py, a, c_max):
    """Earliest arrival of a wave reflected at the far side x = W or the bottom y = -W."""
    far = math.hypot(2 * W - a - px, py)
    bottom = math.hypot(max(abs(px) - a, 0.0), 2 * W + py)
    return min(far, bottom) / c_max


def main_peak(t, s, sign, t0, t1):
    """Index of the largest value of sign * s in [t0, t1]."""
    idx = np.nonzero((t >= t0) & (t <= t1))[0]
    if len(idx) < 3:
        return None
    return idx[np.argmax(sign * s[idx])]


def rise_time(t, s, sign, ip, frac):
    """Time at which sign * s last rises through frac x its value at index ip before ip."""
    y = sign * s
    level = frac * y[ip]
    j = ip
    while j > 0 and y[j] > level:
        j -= 1
    if j == 0:
        return None
    return t[j] + (level - y[j]) / (y[j + 1] - y[j]) * (t[j + 1] - t[j])


def delay(t_sim, s_sim, t_ref, s_ref, t0, t1):
    """Time shift of s_sim against s_ref that minimises their L2 difference over [t0, t1]."""
    grid = np.arange(t0, t1, 0.05e-6)
    a = np.interp(grid, t_ref, s_ref)

    def misfit(tau):
        return np.sum((np.interp(grid + tau, t_sim, s_sim) - a) ** 2)

    taus = np.arange(-3e-6, 3e-6, 0.05e-6)
    vals = [misfit(x) for x in taus]
    i = int(np.argmin(vals))
    if 0 < i < len(taus) - 1:
        y0, y1, y2 = vals[i - 1], vals[i], vals[i + 1]
        den = y0 - 2 * y1 + y2
        return taus[i] + (0.5 * (y0 - y2) / den if den > 0 else 0.0) * (taus[1] - taus[0])
    return taus[i]


def grid(args):
    return dict(dt=0.5e-6, dx=1e-3) if args.coarse else dict(dt=0.25e-6, dx=0.5e-3)


FRACTION = 0.5  # arrival: the last rise through this fraction of the main peak


def fronts(case, out_dir, args):
    c, rho, a = case["c"], case["rho"], case["a"]
    d = read_probes(case, out_dir)
    t_sim = d["time"]
    qp = group_velocity(c, rho, "qP")
    qs = group_velocity(c, rho, "qS")
    c_r = ref.rayleigh_speed(c, rho)
    c_max = math.sqrt(max(c[0], c[2]) / rho)
    stations = []
    for name, x, y in case["probes"]:
        X, Y = lattice_site(x, y, case["radius"])
        stations.append((name, X, Y))
    t_ref, _, v_ref = ref.strip_response(c, rho, a, case["p0"], case["alpha"], case["beta"],
                                         [(x, y) for _, x, y in stations], case["end"], **grid(args))
    ray_angle = math.radians(70.0)
    waves = [  # name, probe prefix, component, sign, theory speed, its speed function
        ("qP along x (surface)", "surface-", "x", +1, float(qp(0.0)), qp),
        ("qP along y (depth)", "axis-", "y", -1, float(qp(math.pi / 2)), qp),
        ("qS along 70 deg", "ray70-", "t", -1, float(qs(ray_angle)), qs),
        ("Rayleigh (surface)", "surface-", "y", -1, c_r, lambda psi: c_r),
    ]
    results = []
    for label, prefix, comp, sign, theory, speed in waves:
        rows = []
        for i, (name, X, Y) in enumerate(stations):
            if not name.startswith(prefix):
                continue
            if prefix != "axis-" and math.hypot(X, Y) < 2.5 * a:
                continue
            if comp == "t":  # transverse to the station's direction from the origin
                psi = math.atan2(-Y, X)
                e = (math.sin(psi), math.cos(psi))
            else:
                e = (1.0, 0.0) if comp == "x" else (0.0, 1.0)
            s_sim = e[0] * d[name + ".velocity_x"] + e[1] * d[name + ".velocity_y"]
            s_ref = e[0] * v_ref[i, 0] + e[1] * v_ref[i, 1]
            t_front = front_time(X, Y, a, speed)
            t_end = min(reflection_time(X, Y, a, c_max), case["end"])
            if prefix == "surface-" and comp == "x":     # qP: before the qS front
                t0, t1 = 0.0, front_time(X, Y, a, qs)
            elif prefix == "axis-":
                t0, t1 = 0.0, t_front + 30e-6
            elif comp == "t":                             # qS: after the qP has passed
                t0, t1 = 0.5 * (front_time(X, Y, a, qp) + t_front), t_end
            else:                                         # Rayleigh: after the qS front
                t0, t1 = front_time(X, Y, a, qs), t_end
            t1 = min(t1, t_end)
            row = dict(station=name, x=X, y=Y, t_front=t_front)
            for kind, tt, ss in (("lattice", t_sim, s_sim), ("continuum", t_ref, s_ref)):
                ip = main_peak(tt, ss, sign, t0, t1)
                if ip is None or ip == np.nonzero(tt <= t1)[0][-1]:
                    row[kind] = None  # the main peak is not inside the window
                    continue
                row[kind] = rise_time(tt, ss, sign, ip, FRACTION)
            if row["lattice"] is not None and row["continuum"] is not None:
                row["delay"] = delay(t_sim, s_sim, t_ref, s_ref, max(t0, row["continuum"] - 10e-6),
                                     min(t1, row["continuum"] + 15e-6))
            rows.append(row)
        ok = [r for r in rows if r.get("delay") is not None]
        res = dict(wave=label, theory=theory, stations=[r["station"] for r in ok], rows=ok)
        if len(ok) >= 3:
            tf = np.array([r["t_front"] for r in ok])
            for kind in ("lattice", "continuum"):
                slope = np.polyfit(tf, np.array([r[kind] for r in ok]), 1)[0]
                res[kind] = theory / slope
            # Lattice against continuum at each station: arrival difference and best time shift.
            res["lattice_vs_continuum"] = theory / (1 + np.polyfit(tf, np.array([r["delay"] for r in ok]), 1)[0])
        results.append(res)

    print("front speeds [m/s] (arrival: %.0f %% of the main peak; slope over the stations)" % (100 * FRACTION))
    print("  %-22s %9s %18s %18s %22s  stations" % ("wave", "theory", "lattice", "continuum",
                                                   "lattice by time shift"))
    bad = []
    for r in results:
        if "lattice" not in r:
            print("  %-22s %9.1f   fewer than 3 stations with the wave inside their window" % (r["wave"], r["theory"]))
            bad.append(r["wave"])
            continue
        e = lambda v: 100 * (v / r["theory"] - 1)
        print("  %-22s %9.1f %9.1f (%+5.2f %%) %9.1f (%+5.2f %%) %12.1f (%+5.2f %%)  %s-%s" % (
            r["wave"], r["theory"], r["lattice"], e(r["lattice"]), r["continuum"], e(r["continuum"]),
            r["lattice_vs_continuum"], e(r["lattice_vs_continuum"]), r["stations"][0], r["stations"][-1]))
        if args.check is not None and abs(r["lattice_vs_continuum"] / r["theory"] - 1) > args.check:
            bad.append(r["wave"])
    if args.json:
        with open(args.json, "w") as f:
            json.dump(dict(radius=case["radius"], fraction=FRACTION, results=results), f, indent=1)
    if args.plot:
        plot_histories(args.plot, stations, t_sim, d, t_ref, v_ref,
                       "%s, r = %.2g mm: lattice (solid) and continuum (dashed)" % (case["name"], case["radius"] * 1e3))
    if args.check is not None:
        if bad:
            sys.exit("front check failed (tolerance %.1f %%): %s" % (100 * args.check, ", ".join(bad)))
        print("front check passed: every lattice front speed (time shift) within %.1f %% of theory" % (100 * args.check))


def lamb(case, out_dir, args):
    c, rho, a = case["c"], case["rho"], case["a"]
    d = read_probes(case, out_dir)
    t_sim = d["time"]
    stations = [(n,) + lattice_site(x, y, case["radius"]) for n, x, y in case["probes"]]
    t_ref, u_ref, v_ref = ref.strip_response(c, rho, a, case["p0"], case["alpha"], case["beta"],
                                             [(x, y) for _, x, y in stations], case["end"], **grid(args))
    c_max = math.sqrt(max(c[0], c[2]) / rho)
    print("Lamb's problem, %s, r = %.3g mm: RMS(lattice - continuum) / peak|continuum| over the window"
          % (case["name"], case["radius"] * 1e3))
    print("  %-12s %8s %10s %12s %12s %12s %12s" % ("station", "x [mm]", "window", "u_y", "v_y", "u_x", "v_x"))
    rows, worst = [], 0.0
    for i, (name, X, Y) in enumerate(stations):
        t_end = min(reflection_time(X, Y, a, c_max), case["end"])
        m = t_sim <= t_end
        row = dict(station=name, x=X, window=t_end)
        for q, arr in (("u", u_ref), ("v", v_ref)):
            for k, comp in enumerate("xy"):
                sim = d["%s.%s_%s" % (name, "displacement" if q == "u" else "velocity", comp)][m]
                r = np.interp(t_sim[m], t_ref, arr[i, k])
                peak = np.max(np.abs(arr[i, k][t_ref <= t_end]))
                # On the symmetry axis u_x vanishes: no relative error there.
                row[q + "_" + comp] = float(np.sqrt(np.mean((sim - r) ** 2)) / peak) if abs(X) > a / 2 or comp == "y" else None
        worst = max(worst, row["v_y"])
        rows.append(row)
        pct = lambda v: "%11.2f%%" % (100 * v) if v is not None else "%12s" % "-"
        print("  %-12s %8.1f %7.0f us %s %s %s %s" % (name, 1e3 * X, 1e6 * t_end, pct(row["u_y"]), pct(row["v_y"]),
                                                     pct(row["u_x"]), pct(row["v_x"])))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(dict(radius=case["radius"], rows=rows), f, indent=1)
    if args.plot:
        plot_histories(args.plot, stations, t_sim, d, t_ref, v_ref,
                       "%s, r = %.2g mm: lattice (solid) and Lamb's problem (dashed)" % (case["name"], case["radius"] * 1e3))
    if args.check is not None:
        if worst > args.check:
            sys.exit("Lamb check failed: vertical velocity error %.2f %% of the peak > %.2f %%" % (100 * worst, 100 * args.check))
        print("Lamb check passed: vertical velocity error at most %.2f %% of the peak (bound %.2f %%)"
              % (100 * worst, 100 * args.check))


def blowup(case, out_dir, args):
    """Growth of the unstable run (rotation_unstable.toml) from its energy rows. The unstable
    modes have negative spring energy (k_s2 < 0) and the total stays balanced, so the growth
    shows in the kinetic energy: the amplitude e-folding time tau comes from the slope of
    ln(kinetic) = 2 t / tau + const over the rows where the kinetic energy exceeds twice the
    input (the growing mode dominates the waves of the load there)."""
    path = os.path.join(out_dir, case["name"] + ".energy.csv")
    try:
        e = np.genfromtxt(path, delimiter=",", names=True)
    except OSError as err:
        fail("%s: %s (run the case first)" % (path, err))
    t, kin, inp = e["time"], e["kinetic"], e["input"]
    grow = np.nonzero(kin > 2.0 * np.maximum(inp, 1e-300))[0]
    print("%s: last good frame t = %.4g us, kinetic / input there %.3g, largest |relative energy error| %.2g"
          % (case["name"], 1e6 * t[-1], kin[-1] / inp[-1], np.max(np.abs(e["relative_error"]))))
    if len(grow) < 2:
        print("  the kinetic energy never exceeded twice the input: no growth to fit")
        return
    fit = np.polyfit(t[grow], np.log(kin[grow]), 1)
    tau = 2.0 / fit[0]
    print("  kinetic energy above twice the input from t = %.4g us; amplitude e-folding time %.3g us "
          "(fit over %d rows, %.4g-%.4g us)" % (1e6 * t[grow[0]], 1e6 * tau, len(grow), 1e6 * t[grow[0]], 1e6 * t[-1]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(dict(last_good_time=float(t[-1]), growth_start=float(t[grow[0]]),
                           efolding_time=float(tau)), f, indent=1)


def plot_histories(path, stations, t_sim, d, t_ref, v_ref, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    groups = sorted(set(n.split("-")[0] for n, _, _ in stations), key=["surface", "axis", "ray70"].index)
    fig, axes = plt.subplots(len(groups), 2, figsize=(12, 3.2 * len(groups)), squeeze=False)
    for g, grp in enumerate(groups):
        for k, comp in enumerate("xy"):
            ax = axes[g, k]
            for i, (name, X, Y) in enumerate(stations):
                if name.split("-")[0] != grp:
                    continue
                line, = ax.plot(1e6 * t_sim, 1e3 * d[name + ".velocity_" + comp], lw=1,
                                label="%s (%.0f mm)" % (name, 1e3 * math.hypot(X, Y)))
                ax.plot(1e6 * t_ref, 1e3 * v_ref[i, k], "--", color=line.get_color(), lw=1)
            ax.set_title("%s stations: v_%s" % (grp, comp), fontsize=9)
            ax.set_xlabel("t [us]")
            ax.set_ylabel("v_%s [mm/s]" % comp)
            ax.grid(alpha=0.3)
        axes[g, 0].legend(fontsize=6, ncol=2)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    import argparse
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("what", choices=["fronts", "lamb", "blowup"])
    p.add_argument("case")
    p.add_argument("out_dir")
    p.add_argument("--check", type=float)
    p.add_argument("--json")
    p.add_argument("--plot")
    p.add_argument("--coarse", action="store_true")
    args = p.parse_args()
    case = read_case(args.case)
    dict(fronts=fronts, lamb=lamb, blowup=blowup)[args.what](case, args.out_dir, args)


if __name__ == "__main__":
    main()

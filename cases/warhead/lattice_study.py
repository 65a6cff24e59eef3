#!/usr/bin/python3
"""Lattice-angle, resolution and seed study of the warhead case (docs/validation.md,
"Fracture that does not depend on the lattice").

    /usr/bin/python3 cases/warhead/lattice_study.py HEXDEM OUT_DIR [--speeds 100 50]
        [--angles 0 10 20 30] [--radii 0.5e-3 0.35e-3] [--seeds 1] [--threads 2]
        [--json FILE] [--reduced] [--control none|broken] [--perturb N] [--delta D]
        [--set KEY=VALUE ...] [--rotate both|target|warhead]

Runs every member (speed x angle x radius x seed) with `hexdem run` and `--set` overrides of
the shipped case files (case.toml at 100 m/s, case_50.toml at 50 m/s, case_25.toml at 25 m/s;
with --reduced, case_ctest.toml at 100 m/s: r = 1 mm, 150 us, the ctest's size):
`mesh.angle` (both bodies; with `--rotate target` or `--rotate warhead` only that body, the
other keeps the angle 0 through its outline's body `angle`), `mesh.radius`, and `random.seed` with `mesh.jitter_seed` (a
member's seed sets its strength field and, with `--set mesh.jitter=F`, its irregular lattice), and any `--set KEY=VALUE` given
here for every member (e.g. `--set material.concrete.nonlocal_radius=4e-3`). `--control none`
runs the study without fracture or plasticity (the concrete's strengths 1e12 Pa, the steel's
yield stress 1e12 Pa), `--control broken` with the disc's bonds broken wherever the stress
waves pass (strengths of 10-100 kPa, brittle): the two controls of docs/validation.md, which show
what the lattice angle moves before any bond breaks and once the bonds have broken; the study
checks that each member is what its control says (no broken bond, no plastic work; over half
of the disc in loose disks) and fails the member otherwise. The disc's rim is put at the first
of 200, 200.2, ..., 201.4 mm at which `hexdem check` accepts the member, so that the clamped
rim set selects disks of a rotated lattice (a set that selects none is refused); the rim used
is in the JSON (`rim_mm`). `--perturb N` runs each member 2 N + 1 times, with the warhead's
speed times 1 + k D, k = -N..N (D = `--delta`, 1e-5 by default): a fracturing impact is
chaotic (docs/validation.md, "Convergence in the time step"), and a member's residual velocity
and cone are one draw of it; the study then also prints, per speed and radius, the mean and
standard deviation at each angle (residual velocity, cone, broken bonds and the booked fracture
energy) and the largest deviation of the angles' means from their mean, to be set against the
standard deviation within an angle. With a step of a few per cent (`--perturb 2 --delta 0.1`:
0.8, 0.9, 1, 1.1 and 1.2 times the speed) the runs are a speed sweep, and the study also prints,
per angle, how many members perforated at each impact speed and, per seed, the ballistic
limit's bracket: the fastest member that did not perforate and the slowest that did (the JSON's
`perforation`). Each member is analysed by
analyse.py; the study prints one row per member and, per speed and radius, the mean and the
largest deviation from the mean of the residual velocity and the cone half-angle, and, with
several seeds, their spread over the seeds at each angle. Exit 0 when every member ran and
was analysed, 1 otherwise (a member that failed is named with its reason), 3 when every member
ran but one completed with a warning (`hexdem run` exit code 3: its energy error passed
[time] energy_warning; the member is in the tables, and named on stderr).
"""

import argparse
import math
import json
import os
import subprocess
import sys

from members import mean_sd, run_and_analyse

HERE = os.path.dirname(os.path.abspath(__file__))
# The controls (docs/validation.md, "What the angle moves before any bond breaks, and once
# the bonds have broken"): overrides of the shipped cases' concrete ("concrete") and steel ("steel").
CONTROLS = {
    "none": ["material.concrete.fracture_energy=0", "material.concrete.tensile_strength=1e12",
             "material.concrete.cohesion=1e12", "material.concrete.compressive_strength=1e13",
             "material.steel.yield_stress=1e12"],
    # The regular lattice's broken crystal: on the shipped irregular lattice ([mesh] jitter) weak
    # bonds break only the disc's middle (docs/validation.md, "An irregular lattice").
    "broken": ["material.concrete.fracture_energy=0", "material.concrete.tensile_strength=1e4",
               "material.concrete.cohesion=1e4", "material.concrete.compressive_strength=1e5",
               "mesh.jitter=0"],
}
BROKEN_LOOSE = 0.5  # --control broken: the least fraction of the disc that must end in loose disks
CASES = {100: "case.toml", 50: "case_50.toml", 25: "case_25.toml"}
REDUCED = {100: "case_ctest.toml"}


def outline_for(case, overrides, work, hexdem, rotate="both"):
    """The case's outline with the disc's rim at the first of 200, 200.2, ..., 201.4 mm where
    `hexdem check` accepts the case (a rotated lattice may have no disk centre within r of
    the rim at 200 mm, and a set that selects no disk is refused). `rotate` names the body
    that `mesh.angle` turns ("both", "target" or "warhead"): the other body is given its own
    `angle = 0`, which the outline format puts before the case's angle."""
    with open(os.path.join(HERE, "outline.toml")) as f:
        text = f.read()
    if "max = [200, 0]" not in text:
        sys.exit("lattice_study.py: outline.toml: the disc's rim 'max = [200, 0]' not found")
    if rotate != "both":
        fixed = {"target": "warhead", "warhead": "target"}[rotate]
        line = 'name = "%s"\n' % fixed
        if text.count(line) != 1:
            sys.exit("lattice_study.py: outline.toml: the body line '%s' not found once" % line.strip())
        text = text.replace(line, line + "angle = 0\n")
    why = ""
    for k in range(8):
        rim = 200.0 + 0.2 * k
        path = os.path.join(work, "outline.toml")
        with open(path, "w") as f:
            f.write(text.replace("max = [200, 0]", "max = [%g, 0]" % rim))
        p = subprocess.run([hexdem, "check", case, "--set", "mesh.outline=%s" % path] + overrides,
                           capture_output=True, text=True)
        if p.returncode == 0:
            return path, rim
        why = p.stderr.strip().splitlines()[-1:] if p.stderr.strip() else "exit %d" % p.returncode
        if "selects no disk" not in p.stderr:
            break
    return None, why


def run_member(args, speed, angle, radius, seed, k=0):
    tag = "v%d_a%g_r%g_s%d" % (speed, angle, radius * 1e3, seed)
    if args.perturb > 0:
        tag += "_k%+d" % k
    work = os.path.join(args.out, tag)
    os.makedirs(work, exist_ok=True)
    case = os.path.join(HERE, (REDUCED if args.reduced else CASES)[speed])
    overrides = ["--set", "mesh.angle=%g" % angle, "--set", "mesh.radius=%g" % radius,
                 "--set", "random.seed=%d" % seed, "--set", "mesh.jitter_seed=%d" % seed]
    if args.perturb > 0:
        overrides += ["--set", "initial_velocity.warhead.velocity=[0, %.17g]" % -perturbed_speed(args, speed, k)]
    for extra in CONTROLS.get(args.control, []) + args.set:
        overrides += ["--set", extra]
    outline, rim = outline_for(case, overrides, work, args.hexdem, args.rotate)
    if outline is None:
        return tag, None, "hexdem check refused every rim position: %s" % rim
    r, _, why = run_and_analyse(args.hexdem, case, work, args.threads,
                                ["--set", "mesh.outline=%s" % outline] + overrides)
    if r is None:
        return tag, None, why
    cone = r["cone"]
    loose = r["pulverised"]["fraction_of_target"]
    plastic = r["energy"]["final"].get("plastic", 0.0)
    if args.control == "none" and (r["broken_bonds"] != 0 or plastic != 0):
        return tag, None, "not a run without fracture: %d broken bonds, %.3g J/rad of plastic work" % (
            r["broken_bonds"], plastic)
    if args.control == "broken" and loose < BROKEN_LOOSE:
        return tag, None, "not a broken disc: %.1f %% of it in loose disks (at least %.0f %%)" % (
            100 * loose, 100 * BROKEN_LOOSE)
    return tag, {
        "speed": speed, "angle": angle, "radius": radius, "seed": seed, "k": k,
        "rim_mm": rim, "outcome": r["outcome"], "residual_velocity": r["residual_velocity_m_s"],
        "max_depth_mm": 1e3 * r["max_penetration_depth_m"],
        "cone_half_angle": cone["half_angle_deg"] if cone.get("formed") else None,
        "broken_bonds": r["broken_bonds"], "loose_fraction": loose,
        "fracture_J_per_rad": r["energy"]["final"].get("fracture", 0.0),
        "max_abs_error": r["energy"]["max_abs_relative_error"],
        "run_warning": r.get("run_warning"),
    }, None


def spread(values):
    values = [v for v in values if v is not None]
    if not values:
        return None, None
    mean = sum(values) / len(values)
    return mean, max(abs(v - mean) for v in values)


def ensemble_tables(args, members):
    """--perturb: each angle's ensemble (mean, standard deviation) and the angles' means against
    their mean, per speed and radius."""
    print()
    print("Ensembles (%d members per angle: seeds x k = -%d..%d):" % (len(args.seeds) * (2 * args.perturb + 1),
                                                                      args.perturb, args.perturb))
    print()
    print("| v [m/s] | r [mm] | angle | outcomes | residual v: mean, sd [m/s] | cone: mean, sd [deg] (members with a cone) "
          "| broken bonds: mean, sd | fracture energy: mean, sd [J/rad] |")
    print("|---|---|---|---|---|---|---|---|")
    out = []
    for speed in args.speeds:
        for radius in args.radii:
            per_angle = []
            for angle in args.angles:
                g = [m for m in members if (m["speed"], m["radius"], m["angle"]) == (speed, radius, angle)]
                if not g:
                    continue
                rv = mean_sd([m["residual_velocity"] for m in g])
                cones = [m["cone_half_angle"] for m in g if m["cone_half_angle"] is not None]
                ca = mean_sd(cones)
                bb = mean_sd([m["broken_bonds"] for m in g])
                fe = mean_sd([m["fracture_J_per_rad"] for m in g])
                outcomes = sorted(set(m["outcome"] for m in g))
                per_angle.append({"angle": angle, "members": len(g), "outcomes": outcomes, "residual": rv,
                                  "cone": ca, "cones": len(cones), "broken_bonds": bb, "fracture": fe})
                print("| %d | %g | %g | %s | %+.1f, %.1f | %s | %.0f, %.0f | %.3f, %.3f |"
                      % (speed, radius * 1e3, angle, ", ".join(outcomes), rv[0], rv[1],
                         "%.1f, %.1f (%d of %d)" % (ca[0], ca[1], len(cones), len(g)) if ca[0] is not None
                         else "no cone", bb[0], bb[1], fe[0], fe[1]))
            if not per_angle:
                continue
            rv_means = [a["residual"][0] for a in per_angle]
            ca_means = [a["cone"][0] for a in per_angle if a["cone"][0] is not None]
            row = {"speed": speed, "radius": radius, "angles": per_angle,
                   "residual_mean": sum(rv_means) / len(rv_means),
                   "cone_mean": sum(ca_means) / len(ca_means) if ca_means else None}
            row["residual_deviation"] = max(abs(v - row["residual_mean"]) for v in rv_means)
            row["cone_deviation"] = max(abs(v - row["cone_mean"]) for v in ca_means) if ca_means else None
            # Pooled standard deviation within the angles: the chaos (and disorder) of one member.
            row["residual_sd_within"] = (sum(a["residual"][1] ** 2 for a in per_angle) / len(per_angle)) ** 0.5
            sds = [a["cone"][1] for a in per_angle if a["cone"][0] is not None]
            row["cone_sd_within"] = (sum(v * v for v in sds) / len(sds)) ** 0.5 if sds else None
            # The booked fracture energy: the angles' means, their largest deviation from their
            # mean relative to it, and the spread within an angle (docs/validation.md, "Where
            # the lattice angle's damage is").
            fe_means = [a["fracture"][0] for a in per_angle]
            row["fracture_mean"] = sum(fe_means) / len(fe_means)
            row["fracture_deviation"] = max(abs(v - row["fracture_mean"]) for v in fe_means)
            row["fracture_sd_within"] = (sum(a["fracture"][1] ** 2 for a in per_angle) / len(per_angle)) ** 0.5
            out.append(row)
    print()
    print("| v [m/s] | r [mm] | angles' mean residual v: mean, largest deviation | sd within an angle | "
          "angles' mean cone: mean, largest deviation | sd within an angle | "
          "angles' mean fracture energy: mean, largest deviation | sd within an angle |")
    print("|---|---|---|---|---|---|---|---|")
    for row in out:
        print("| %d | %g | %+.1f, %.1f m/s | %.1f m/s | %s | %s | %.3f, %.3f J/rad (%.0f %%) | %.3f J/rad |"
              % (row["speed"], row["radius"] * 1e3, row["residual_mean"], row["residual_deviation"],
                 row["residual_sd_within"],
                 "%.1f, %.1f deg" % (row["cone_mean"], row["cone_deviation"]) if row["cone_mean"] is not None
                 else "no cone",
                 "%.1f deg" % row["cone_sd_within"] if row["cone_sd_within"] is not None else "n/a",
                 row["fracture_mean"], row["fracture_deviation"],
                 100 * row["fracture_deviation"] / row["fracture_mean"] if row["fracture_mean"] > 0 else 0.0,
                 row["fracture_sd_within"]))
    return out


def impact_speed(args, m):
    """The member's impact speed [m/s]: the case's speed times 1 + k D."""
    return perturbed_speed(args, m["speed"], m.get("k", 0))


def perturbed_speed(args, speed, k):
    """Speed times 1 + k D [m/s] (--perturb, --delta)."""
    return speed * (1 + k * args.delta)


def logistic_limit(points):
    """Maximum-likelihood fit of P(perforation) = 1 / (1 + exp(-(v - v50) / s)) to (v, perforated)
    pairs, on a grid (v50 in steps of 0.05 m/s over the speeds run, +-5 m/s; s from 0.1 to 20 m/s);
    None where the members do not bracket a limit (all or none perforated)."""
    hits = [p for _, p in points]
    if all(hits) or not any(hits):
        return None
    lo = min(v for v, _ in points) - 5
    hi = max(v for v, _ in points) + 5
    best = None
    for i in range(int(round((hi - lo) / 0.05)) + 1):
        v50 = lo + 0.05 * i
        for j in range(61):
            s = 0.1 * 200 ** (j / 60)
            ll = 0.0
            for v, p in points:
                z = max(-700.0, min(700.0, (v - v50) / s))
                q = 1 / (1 + math.exp(-z))
                q = min(max(q, 1e-12), 1 - 1e-12)
                ll += math.log(q if p else 1 - q)
            if best is None or ll > best[0]:
                best = (ll, v50)
    return best[1]


def limit_bracket(args, group):
    """The ballistic limit's bracket of one seed's members (one per k): the fastest member that
    did not perforate and the slowest that did (None where there is none); `ordered` is false
    when a slower member perforated and a faster one did not."""
    below = [impact_speed(args, m) for m in group if m["outcome"] != "perforation"]
    above = [impact_speed(args, m) for m in group if m["outcome"] == "perforation"]
    low = max(below) if below else None
    high = min(above) if above else None
    return {"low": low, "high": high, "ordered": low is None or high is None or low < high}


def bracket_text(b):
    if b["low"] is None and b["high"] is None:
        return "none"
    if b["high"] is None:
        return "above %.4g" % b["low"]
    if b["low"] is None:
        return "below %.4g" % b["high"]
    if not b["ordered"]:
        return "not ordered (%.4g perforated, %.4g did not)" % (b["high"], b["low"])
    return "%.4g-%.4g" % (b["low"], b["high"])


def perforation_table(args, members):
    """--perturb with a speed step (D of a few %): per speed, radius and angle, how many members
    perforated at each impact speed v (1 + k D), and per seed the ballistic limit's bracket
    (docs/validation.md, "The ballistic limit over the lattice angles")."""
    ks = list(range(-args.perturb, args.perturb + 1))
    out = []
    print()
    print("Perforation by impact speed (members that perforated of those run; per seed, the ballistic limit "
          "lies between the fastest member that did not perforate and the slowest that did):")
    for speed in args.speeds:
        speeds = [perturbed_speed(args, speed, k) for k in ks]
        print()
        print("| v [m/s] | r [mm] | angle | " + " | ".join("%.4g m/s" % v for v in speeds)
              + " | limit per seed [m/s] | logistic fit of the limit [m/s] |")
        print("|---|---|---|" + "---|" * len(speeds) + "---|---|")
        for radius in args.radii:
            for angle in args.angles:
                g = [m for m in members if (m["speed"], m["radius"], m["angle"]) == (speed, radius, angle)]
                if not g:
                    continue
                counts = []
                for k in ks:
                    sel = [m for m in g if m.get("k", 0) == k]
                    counts.append([sum(m["outcome"] == "perforation" for m in sel), len(sel)])
                brackets = {seed: limit_bracket(args, [m for m in g if m["seed"] == seed])
                            for seed in sorted(set(m["seed"] for m in g))}
                fit = logistic_limit([(impact_speed(args, m), m["outcome"] == "perforation") for m in g])
                print("| %d | %g | %g | %s | %s | %s |" % (
                    speed, radius * 1e3, angle, " | ".join("%d/%d" % (c[0], c[1]) for c in counts),
                    "; ".join("%d: %s" % (seed, bracket_text(b)) for seed, b in brackets.items()),
                    "%.1f" % fit if fit is not None else "none"))
                out.append({"speed": speed, "radius": radius, "angle": angle, "impact_speeds": speeds,
                            "perforated": counts, "brackets": {str(k): b for k, b in brackets.items()},
                            "logistic_limit": fit})
    return out


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("hexdem")
    parser.add_argument("out")
    parser.add_argument("--speeds", type=int, nargs="+", default=[100, 50], choices=sorted(CASES))
    parser.add_argument("--angles", type=float, nargs="+", default=[0, 10, 20, 30])
    parser.add_argument("--radii", type=float, nargs="+", default=[0.5e-3, 0.35e-3])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1])
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--json")
    parser.add_argument("--perturb", type=int, default=0, metavar="N",
                        help="run each member at the speed times 1 + k D, k = -N..N (default 0)")
    parser.add_argument("--delta", type=float, default=1e-5, metavar="D")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a further `hexdem run --set` override for every member (repeatable)")
    parser.add_argument("--reduced", action="store_true", help="case_ctest.toml (100 m/s only)")
    parser.add_argument("--rotate", choices=["both", "target", "warhead"], default="both",
                        help="the body that --angles turns; the other stays at 0 degrees (default both)")
    parser.add_argument("--control", choices=sorted(CONTROLS),
                        help="none: no fracture or plasticity; broken: the disc's bonds broken by the stress waves")
    args = parser.parse_args(argv)
    if args.perturb < 0 or not args.delta > 0:
        parser.error("--perturb must be >= 0 and --delta > 0")
    if args.reduced and args.speeds != [100]:
        parser.error("--reduced has 100 m/s only (--speeds 100)")
    # Absolute: the members' outlines are given to hexdem, which resolves a relative path
    # against the case file's folder, not the working directory.
    args.out = os.path.abspath(args.out)
    os.makedirs(args.out, exist_ok=True)
    members, failed = [], []
    print("| v [m/s] | r [mm] | angle | seed | outcome | residual v [m/s] | max depth [mm] | "
          "cone half-angle [deg] | broken bonds | max \\|Err\\| |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for speed in args.speeds:
        for radius in args.radii:
            for angle in args.angles:
                for seed, k in [(s, k) for s in args.seeds for k in range(-args.perturb, args.perturb + 1)]:
                    tag, m, why = run_member(args, speed, angle, radius, seed, k)
                    if m is None:
                        failed.append((tag, why))
                        print("| %s | failed: %s |" % (tag, why), flush=True)
                        continue
                    members.append(m)
                    cone = "%.1f" % m["cone_half_angle"] if m["cone_half_angle"] is not None else "no cone"
                    print("| %d | %g | %g | %s | %s | %+.1f | %.1f | %s | %d | %.1e |"
                          % (speed, radius * 1e3, angle, seed if args.perturb == 0 else "%d, k %+d" % (seed, k),
                             m["outcome"], m["residual_velocity"], m["max_depth_mm"], cone, m["broken_bonds"],
                             m["max_abs_error"]), flush=True)
    print()
    print("| v [m/s] | r [mm] | outcomes | residual v: mean, largest deviation | "
          "cone half-angle: mean, largest deviation (angles with a cone) |")
    print("|---|---|---|---|---|")
    groups = []
    for speed in args.speeds:
        for radius in args.radii:
            g = [m for m in members if m["speed"] == speed and m["radius"] == radius]
            if not g:
                continue
            rv = spread([m["residual_velocity"] for m in g])
            ca = spread([m["cone_half_angle"] for m in g])
            outcomes = sorted(set(m["outcome"] for m in g))
            cones = sum(m["cone_half_angle"] is not None for m in g)
            groups.append({"speed": speed, "radius": radius, "outcomes": outcomes,
                           "residual_mean": rv[0], "residual_deviation": rv[1],
                           "cone_mean": ca[0], "cone_deviation": ca[1], "cones": cones, "members": len(g)})
            print("| %d | %g | %s | %+.1f, %.1f m/s | %s |"
                  % (speed, radius * 1e3, ", ".join(outcomes), rv[0], rv[1],
                     "%.1f, %.1f deg (%d of %d)" % (ca[0], ca[1], cones, len(g)) if ca[0] is not None
                     else "no cone"))
    if len(args.seeds) > 1:
        print()
        print("Spread over the seeds (largest minus smallest) at each angle:")
        for speed in args.speeds:
            for radius in args.radii:
                for angle in args.angles:
                    g = [m for m in members if (m["speed"], m["radius"], m["angle"]) == (speed, radius, angle)]
                    if len(g) < 2:
                        continue
                    rv = [m["residual_velocity"] for m in g]
                    ca = [m["cone_half_angle"] for m in g if m["cone_half_angle"] is not None]
                    print("  %d m/s, r %g mm, %g deg: residual v %.1f m/s, cone %s" % (
                        speed, radius * 1e3, angle, max(rv) - min(rv),
                        "%.1f deg (%d of %d with a cone)" % (max(ca) - min(ca), len(ca), len(g)) if ca else "none"))
    ensembles = ensemble_tables(args, members) if args.perturb > 0 else []
    perforation = perforation_table(args, members) if args.perturb > 0 else []
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"control": args.control, "rotate": args.rotate, "members": members, "groups": groups, "ensembles": ensembles,
                       "perforation": perforation, "failed": failed}, f, indent=1)
    for tag, why in failed:
        sys.stderr.write("lattice_study.py: %s: %s\n" % (tag, why))
    warned = [m for m in members if m.get("run_warning")]
    for m in warned:
        sys.stderr.write("lattice_study.py: v%d a%g r%g s%d completed with a warning: %s\n"
                         % (m["speed"], m["angle"], m["radius"] * 1e3, m["seed"], m["run_warning"]))
    return 1 if failed else 3 if warned else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

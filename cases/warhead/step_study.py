#!/usr/bin/python3
"""Convergence of the warhead case in the time step (docs/validation.md, "Convergence in the
time step").

    /usr/bin/python3 cases/warhead/step_study.py HEXDEM OUT_DIR [--case case.toml]
        [--factors 0.5 1 1.36] [--perturb 3] [--delta 1e-5] [--threads 2] [--json FILE]
        [--set KEY=VALUE ...]

A fracturing impact is chaotic: which bond breaks first decides where the next crack runs, and
an impact speed changed by one part in 100,000 already moves the broken bonds by a few % and
the residual velocity by metres per second. One run per step therefore cannot tell the step's
effect from that chaos. For each step factor f (the step used is f times the case's default
step, `hexdem check`'s "time step", given as `[time] dt` with `allow_unstable`, so that f above
1/0.9, beyond the critical step, can be run), the study runs 2 n + 1 members whose warhead speed is v0 (1 + k delta), k = -n..n, and
reports the mean and standard deviation over them of the broken bonds, the fracture energy,
the residual velocity and the cone half-angle (analyse.py). The case must be one of this
folder's (its [[initial_velocity]] is the body "warhead"'s, overridden with `--set
initial_velocity.warhead.velocity=...`). The contacts' stiffness cap is the
default step's whatever the step (docs/model.md, "Energy at contacts"), so every member has the
same model and only its integration differs. The step's effect is the difference of the means;
the chaos is the standard deviation (divide by sqrt(2 n + 1) for the means' own uncertainty).

Exit 0 when every member ran and was analysed, 1 otherwise, 3 when a member completed with a
warning (`hexdem run` exit code 3).
"""

import argparse
import json
import os
import re
import subprocess
import sys

from members import mean_sd, run_and_analyse

HERE = os.path.dirname(os.path.abspath(__file__))


def default_step(args):
    """The case's default step [s] and the warhead's initial velocity, from `hexdem check`."""
    p = subprocess.run([args.hexdem, "check", args.case] + sum((["--set", s] for s in args.set), []),
                       capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("step_study.py: hexdem check %s: exit %d: %s" % (args.case, p.returncode, p.stderr.strip()))
    m = re.search(r"time step ([0-9.eE+-]+) s \(safety x critical", p.stdout)
    if m is None:
        sys.exit("step_study.py: %s: the case gives its own [time] dt; the study needs the default step" % args.case)
    with open(args.case) as f:
        v = re.search(r"velocity = \[\s*([0-9.eE+-]+)\s*,\s*([0-9.eE+-]+)\s*\]", f.read())
    if v is None:
        sys.exit("step_study.py: %s: no [[initial_velocity]] velocity = [vx, vy] found" % args.case)
    return float(m.group(1)), (float(v.group(1)), float(v.group(2)))


def run_member(args, dt0, v0, factor, k):
    tag = "f%g_k%+d" % (factor, k)
    work = os.path.join(args.out, tag)
    os.makedirs(work, exist_ok=True)
    s = 1.0 + k * args.delta
    overrides = ["--set", "initial_velocity.warhead.velocity=[%.17g, %.17g]" % (v0[0] * s, v0[1] * s)]
    if factor != 1.0:
        overrides += ["--set", "time.dt=%.17g" % (factor * dt0), "--set", "time.allow_unstable=true"]
    for extra in args.set:
        overrides += ["--set", extra]
    r, warned, why = run_and_analyse(args.hexdem, args.case, work, args.threads, overrides)
    if r is None:
        return tag, None, why
    cone = r["cone"]
    return tag, {
        "factor": factor, "k": k, "dt": factor * dt0, "outcome": r["outcome"],
        "residual_velocity": r["residual_velocity_m_s"],
        "cone_half_angle": cone["half_angle_deg"] if cone.get("formed") else None,
        "broken_bonds": r["broken_bonds"], "fracture": r["energy"]["final"].get("fracture", 0.0),
        "max_abs_error": r["energy"]["max_abs_relative_error"], "warned": warned,
    }, None


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("hexdem")
    parser.add_argument("out")
    parser.add_argument("--case", default=os.path.join(HERE, "case.toml"))
    parser.add_argument("--factors", type=float, nargs="+", default=[0.5, 1.0, 1.36])
    parser.add_argument("--perturb", type=int, default=3, help="n: members k = -n..n per step")
    parser.add_argument("--delta", type=float, default=1e-5, help="relative speed change per k")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--json")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="a further `hexdem run --set` override for every member (repeatable)")
    args = parser.parse_args(argv)
    if any(not (f > 0) for f in args.factors) or args.perturb < 0 or not (args.delta > 0):
        parser.error("--factors must be > 0, --perturb >= 0, --delta > 0")
    args.out = os.path.abspath(args.out)
    args.case = os.path.abspath(args.case)
    os.makedirs(args.out, exist_ok=True)
    dt0, v0 = default_step(args)
    print("default step %.6g s, warhead velocity [%g, %g] m/s, members per step %d (delta %g)"
          % (dt0, v0[0], v0[1], 2 * args.perturb + 1, args.delta))
    print()
    print("| step factor | k | outcome | residual v [m/s] | cone half-angle [deg] | broken bonds | "
          "fracture [J/rad] | max \\|Err\\| |")
    print("|---|---|---|---|---|---|---|---|")
    members, failed = [], []
    for factor in args.factors:
        for k in range(-args.perturb, args.perturb + 1):
            tag, m, why = run_member(args, dt0, v0, factor, k)
            if m is None:
                failed.append((tag, why))
                print("| %s | failed: %s |" % (tag, why), flush=True)
                continue
            members.append(m)
            cone = "%.1f" % m["cone_half_angle"] if m["cone_half_angle"] is not None else "no cone"
            print("| %g | %+d | %s | %+.2f | %s | %d | %.4f | %.1e |"
                  % (factor, k, m["outcome"], m["residual_velocity"], cone, m["broken_bonds"], m["fracture"],
                     m["max_abs_error"]), flush=True)
    print()
    print("| step factor | dt [s] | members | outcomes | broken bonds: mean, sd | fracture [J/rad]: mean, sd | "
          "residual v [m/s]: mean, sd | cone [deg]: mean, sd | worst max \\|Err\\| |")
    print("|---|---|---|---|---|---|---|---|---|")
    groups = []
    for factor in args.factors:
        g = [m for m in members if m["factor"] == factor]
        if not g:
            continue
        row = {"factor": factor, "dt": factor * dt0, "members": len(g),
               "outcomes": sorted(set(m["outcome"] for m in g)),
               "worst_error": max(m["max_abs_error"] for m in g)}
        for key in ("broken_bonds", "fracture", "residual_velocity", "cone_half_angle"):
            row[key] = mean_sd([m[key] for m in g])
        groups.append(row)

        def ms(pair, fmt):
            return "n/a" if pair[0] is None else (fmt % pair[0]) + ", " + (fmt % pair[1])
        print("| %g | %.4g | %d | %s | %s | %s | %s | %s | %.1e |"
              % (factor, factor * dt0, len(g), ", ".join(row["outcomes"]), ms(row["broken_bonds"], "%.0f"),
                 ms(row["fracture"], "%.3f"), ms(row["residual_velocity"], "%+.2f"),
                 ms(row["cone_half_angle"], "%.1f"), row["worst_error"]))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"default_step": dt0, "delta": args.delta, "members": members, "groups": groups,
                       "failed": failed}, f, indent=1)
    for tag, why in failed:
        print("step_study.py: %s: %s" % (tag, why), file=sys.stderr)
    if failed:
        return 1
    return 3 if any(m["warned"] for m in members) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

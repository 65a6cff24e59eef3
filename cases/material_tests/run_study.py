#!/usr/bin/env python3
"""Runs a virtual material test over lattice angles, radii or random-field seeds and reports
the mean and the spread of its results (cases/material_tests/README.md).

    run_study.py KIND [--angles 0,10,20,30] [--radii R1,R2,...] [--seeds S1,S2,...]
                 [--out DIR] [--jobs N] [--hexdem PATH] [--set KEY=VALUE ...] [--json FILE]

KIND is tension, compression, brazilian or notched_beam (the case KIND.toml beside this
script). Every combination of the lists is one run of `hexdem run KIND.toml --set ...` in its
own folder under DIR, analysed by analyse.py. Prints one line per run, then for each result
its mean, the spread (max - min) and the largest deviation from the mean in % of the mean.
Exits 1 if a run or its analysis fails, a --check, --max or --min limit is passed, or (--strict) a run
fails one of analyse.py's own checks; otherwise 3 if a run completed with a warning (`hexdem
run` exit code 3: its energy error passed [time] energy_warning; analyse.py records it as the
result's "run_warning"), else 0.
"""
import argparse
import concurrent.futures
import itertools
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
KEYS = {"tension": "peak_stress_MPa", "compression": "peak_stress_MPa", "brazilian": "split_strength_MPa",
        "notched_beam": "peak_load_N"}


def numbers(text):
    return [float(v) for v in text.split(",")] if text else [None]


def run_case(hexdem, case, kind, out, sets):
    """`hexdem run CASE --set ...` into OUT, then analyse.py; returns (result or None, line)."""
    cmd = [hexdem, "run", case, "--out", out, "--threads", "1", "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode not in (0, 3):  # 3: completed with a warning (analysed, and reported)
        return None, "run failed (exit %d): %s" % (r.returncode, r.stderr.strip().splitlines()[-1:] or "")
    js = out + ".json"
    a = subprocess.run([sys.executable, os.path.join(HERE, "analyse.py"), kind,
                        os.path.join(out, kind + ".pvd"), "--json", js], capture_output=True, text=True)
    if a.returncode != 0:
        return None, "analysis failed: " + a.stderr.strip()
    with open(js) as f:
        return json.load(f), a.stdout.strip() + (" " + a.stderr.strip() if a.stderr.strip() else "")


def run_all(jobs, fn, combos):
    """fn(combo) -> (tag, result or None, line) over the combos on `jobs` workers; prints one
    line per run and returns (every run succeeded, the results)."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        results = list(pool.map(fn, combos))
    ok = True
    rows = []
    for tag, res, line in results:
        print("%-16s %s" % (tag, line))
        if res is None:
            ok = False
        else:
            rows.append(res)
    return ok, rows


def spread_of(vals):
    """The mean, the spread (max - min) and the largest deviation from the mean in % of it."""
    mean = sum(vals) / len(vals)
    dev = max(abs(v - mean) for v in vals)
    return {"mean": mean, "spread": max(vals) - min(vals), "max_dev_pct": 100 * dev / abs(mean) if mean else float("nan")}


def spread_line(s):
    """spread_of's figures as printed by the studies."""
    return "mean %-10.4g spread %-10.4g max deviation %.2f %% of the mean" % (s["mean"], s["spread"], s["max_dev_pct"])


def run_one(args, angle, radius, seed):
    tag = "a%g" % angle if angle is not None else "a-"
    tag += "_r%g" % radius if radius is not None else ""
    tag += "_s%d" % seed if seed is not None else ""
    out = os.path.join(args.out, args.kind, tag)
    sets = list(args.set or [])
    if angle is not None:
        sets.append("mesh.angle=%g" % angle)
    if radius is not None:
        sets.append("mesh.radius=%g" % radius)
    if seed is not None:
        sets.append("random.seed=%d" % seed)
        sets.append("mesh.jitter_seed=%d" % seed)
    res, line = run_case(args.hexdem, os.path.join(HERE, args.kind + ".toml"), args.kind, out, sets)
    return tag, res, line


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("kind", choices=sorted(KEYS))
    ap.add_argument("--angles", default="0,10,20,30")
    ap.add_argument("--radii", default="")
    ap.add_argument("--seeds", default="")
    ap.add_argument("--out", default=os.path.join(os.getcwd(), "material_tests_study"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--hexdem", default=os.path.join(REPO, "build", "release", "solver", "hexdem"))
    ap.add_argument("--set", action="append")
    ap.add_argument("--json")
    ap.add_argument("--check", action="append", default=[],
                    help="KEY=PCT: exit 1 if a result's largest deviation from its mean exceeds PCT %%")
    ap.add_argument("--max", action="append", default=[],
                    help="KEY=VALUE: exit 1 if a result exceeds VALUE in some run")
    ap.add_argument("--min", action="append", default=[],
                    help="KEY=VALUE: exit 1 if a result is below VALUE in some run")
    ap.add_argument("--strict", action="store_true",
                    help="exit 1 if a run fails one of analyse.py's own checks (they are printed anyway)")
    args = ap.parse_args(argv)
    combos = list(itertools.product(numbers(args.angles), numbers(args.radii),
                                    [int(s) if s is not None else None for s in numbers(args.seeds)]))
    ok, rows = run_all(args.jobs, lambda c: run_one(args, *c), combos)
    summary = {}
    if rows:
        for key in [k for k, v in rows[0].items() if isinstance(v, (int, float)) and not isinstance(v, bool)
                    and k not in ("angle", "radius", "seed")]:
            vals = [r[key] for r in rows if isinstance(r.get(key), (int, float))]
            if not vals:
                continue
            summary[key] = dict(spread_of(vals), values=vals)
            print("%-28s %s" % (key, spread_line(summary[key])))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"runs": rows, "summary": summary}, f, indent=1)
    for spec in args.check:
        key, pct = spec.split("=")
        dev = summary.get(key, {}).get("max_dev_pct", float("inf"))
        if not dev <= float(pct):
            print("check failed: %s deviates %.2f %% from its mean (limit %s %%)" % (key, dev, pct))
            ok = False
    for spec in args.max:
        key, limit = spec.split("=")
        for r in rows:
            if not r.get(key, float("inf")) <= float(limit):
                print("check failed: %s = %s above %s in the run at angle %s, radius %s, seed %s" %
                      (key, r.get(key), limit, r["angle"], r["radius"], r["seed"]))
                ok = False
    for spec in args.min:
        key, limit = spec.split("=")
        for r in rows:
            if not r.get(key, -float("inf")) >= float(limit):
                print("check failed: %s = %s below %s in the run at angle %s, radius %s, seed %s" %
                      (key, r.get(key), limit, r["angle"], r["radius"], r["seed"]))
                ok = False
    failed = [r for r in rows if not all(r.get("checks", {}).values())]
    for r in failed:
        print("%s in the run at angle %s, radius %s, seed %s: %s" %
              ("check failed" if args.strict else "not met (reported)", r["angle"], r["radius"], r["seed"],
               ", ".join(k for k, v in r["checks"].items() if not v)))
    warned = [r for r in rows if r.get("run_warning")]  # from the run's status (analyse.py)
    for r in warned:
        print("warning in the run at angle %s, radius %s, seed %s: %s" % (r["angle"], r["radius"], r["seed"],
                                                                         r["run_warning"]))
    if not ok or (failed and args.strict):
        sys.exit(1)
    sys.exit(3 if warned else 0)


if __name__ == "__main__":
    main(sys.argv[1:])

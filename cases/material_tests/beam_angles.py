#!/usr/bin/env python3
"""The notched beam over lattice angles, its hinges moved onto the rotated lattice.

    beam_angles.py [--angles 0,10,20,30] [--radii 0.004] [--out DIR] [--jobs N] [--hexdem PATH]
                   [--json FILE]

The beam's supports are 0.2 mm edges at x = -1 and +1 m that hold the one disk nearest to each
(notched_beam.toml). On a rotated lattice no disk may lie within a radius of such an edge, and
`hexdem check` refuses the case, naming the support (docs/case-format.md, "Checks"). For every
angle and radius this script moves each support edge along the bottom, independently, by
0, +-r/4, +-r/2, ... up to +-2r, until the check passes, writes that case beside the run, runs
it with `hexdem run` and analyses it with analyse.py, as run_study.py does. The span changes by
the two moves (printed with every run: at most 4r, 0.8 % of the 2 m span at r = 4 mm; the peak
of a beam scales about as 1 / span). Prints one line per run, then the mean, the spread and the
largest deviation from the mean of every result.

Exit 1 if a run or its analysis fails or no placement passes the check, 2 on bad arguments.
"""
import argparse
import itertools
import json
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from run_study import run_all, run_case, spread_line, spread_of  # noqa: E402
REPO = os.path.dirname(os.path.dirname(HERE))
CASE = os.path.join(HERE, "notched_beam.toml")
LEFT = "[-1000.1, 0.0], [-999.9, 0.0]"
RIGHT = "[999.9, 0.0], [1000.1, 0.0]"


def fail(msg, code=2):
    print("beam_angles.py: " + msg, file=sys.stderr)
    sys.exit(code)


def numbers(text, what):
    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        fail("%s: not a list of numbers: %r" % (what, text))


def case_text(base, dl, dr):
    """The case with the left support moved by dl and the right one by dr [mm]."""
    left = "[%.4f, 0.0], [%.4f, 0.0]" % (-1000.1 + dl, -999.9 + dl)
    right = "[%.4f, 0.0], [%.4f, 0.0]" % (999.9 + dr, 1000.1 + dr)
    return base.replace(LEFT, left).replace(RIGHT, right)


def place(args, base, angle, radius, folder):
    """Moves the supports until `hexdem check` passes; returns (path, dl, dr) or an error."""
    r_mm = radius * 1e3
    steps = [0.0] + [s * k * r_mm / 4 for k in range(1, 9) for s in (1, -1)]
    il = ir = 0
    path = os.path.join(folder, "notched_beam.toml")
    while il < len(steps) and ir < len(steps):
        with open(path, "w") as f:
            f.write(case_text(base, steps[il], steps[ir]))
        c = subprocess.run([args.hexdem, "check", path, "--set", "mesh.angle=%g" % angle,
                            "--set", "mesh.radius=%g" % radius], capture_output=True, text=True)
        if c.returncode == 0:
            return path, steps[il], steps[ir], None
        err = c.stderr.strip()
        m = re.search(r"boundary set 'support' holds no disk on its part near \(([-0-9.e+]+),", err)
        if m:
            if float(m.group(1)) < 0:
                il += 1
            else:
                ir += 1
        elif "boundary set 'support' selects no disk" in err:
            il += 1
            ir += 1
        else:
            return None, 0, 0, "hexdem check failed: " + (err.splitlines()[-1] if err else "exit %d" % c.returncode)
    return None, 0, 0, "no placement of the supports within 2r holds a disk at each"


def run_one(args, base, angle, radius):
    tag = "a%g_r%g" % (angle, radius)
    folder = os.path.join(args.out, tag)
    os.makedirs(folder, exist_ok=True)
    path, dl, dr, err = place(args, base, angle, radius, folder)
    if err:
        return tag, None, err
    res, line = run_case(args.hexdem, path, "notched_beam", os.path.join(folder, "run"),
                         ["mesh.angle=%g" % angle, "mesh.radius=%g" % radius])
    if res is None:
        return tag, None, line
    res["support_shift_mm"] = [dl, dr]
    res["span_mm"] = 2000.0 + dr - dl
    return tag, res, "supports moved %+.2f / %+.2f mm (span %.2f mm) %s" % (dl, dr, res["span_mm"], line)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--angles", default="0,10,20,30")
    ap.add_argument("--radii", default="0.004")
    ap.add_argument("--out", default=os.path.join(os.getcwd(), "beam_angles"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--hexdem", default=os.path.join(REPO, "build", "release", "solver", "hexdem"))
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    angles = numbers(a.angles, "--angles")
    radii = numbers(a.radii, "--radii")
    if not angles or not radii or any(r <= 0 for r in radii):
        fail("--angles and --radii need at least one value each, radii > 0: %r, %r" % (a.angles, a.radii))
    if a.jobs < 1:
        fail("--jobs: must be at least 1: %d" % a.jobs)
    if not os.access(a.hexdem, os.X_OK):
        fail("--hexdem: not an executable: %s" % a.hexdem)
    with open(CASE) as f:
        base = f.read()
    if LEFT not in base or RIGHT not in base:
        fail("%s: the support edges %s and %s are not in the outline" % (CASE, LEFT, RIGHT), 1)
    ok, rows = run_all(a.jobs, lambda c: run_one(a, base, *c), itertools.product(angles, radii))
    summary = {}
    for radius in radii:
        group = [r for r in rows if r["radius"] == radius]
        for key in ("peak_load_N", "work_of_fracture_J_m2", "fracture_energy_over_ligament_J_m2",
                    "broken_facet_length_mm", "open_facet_length_mm", "max_energy_error"):
            vals = [r[key] for r in group]
            if not vals:
                continue
            s = summary.setdefault("r%g" % radius, {})[key] = spread_of(vals)
            print("r = %g m  %-36s %s" % (radius, key, spread_line(s)))
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"runs": rows, "summary": summary}, f, indent=1)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

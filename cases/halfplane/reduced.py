#!/usr/bin/env python3
"""Reduced versions of the half-plane cases for ctest (tests/cases/halfplane.cmake): the same
case files with a coarser lattice, checked by analyze.py.

    python3 reduced.py HEXDEM WORK_DIR fronts   [--radius R]   front speeds (fronts.toml)
    python3 reduced.py HEXDEM WORK_DIR lamb     [--radius R]   Lamb's problem (lamb.toml)
    python3 reduced.py HEXDEM WORK_DIR rotation                the paper's shear model (rotation.toml)

fronts and lamb run with r = 1 mm (--radius, metres; 18,000 disks instead of 72,000) and
fail unless, respectively, every front speed measured by the time shift against the continuum
solution lies within FRONT_TOL of theory, and the surface vertical velocity differs from
Lamb's solution by less than LAMB_BOUND of its peak (RMS) at every station; the bounds are
justified in README.md. rotation fails unless hexdem refuses rotation.toml with exit status 2
and the stability message.
"""
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
FRONT_TOL = 0.01    # fraction: |lattice speed / theory - 1|, r = 1 mm
LAMB_BOUND = 0.06   # RMS(v_y lattice - v_y Lamb) / peak |v_y Lamb|, r = 1 mm


def variant(src, work, radius):
    """Copies a case file into WORK_DIR with [mesh] radius = RADIUS and an absolute outline path."""
    with open(os.path.join(HERE, src)) as f:
        text = f.read()
    text = text.replace('outline = "outline.toml"',
                        'outline = "%s"\nradius = %.17g' % (os.path.join(HERE, "outline.toml"), radius))
    path = os.path.join(work, src.replace(".toml", "_r%g.toml" % (radius * 1e3)))
    with open(path, "w") as f:
        f.write(text)
    return path


def run(hexdem, case, out):
    p = subprocess.run([hexdem, "run", case, "--out", out, "-q"], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("reduced.py: hexdem run %s failed (%d): %s" % (case, p.returncode, p.stderr.strip()))


def main():
    if len(sys.argv) < 4 or sys.argv[3] not in ("fronts", "lamb", "rotation"):
        sys.exit(__doc__)
    hexdem, work, what = sys.argv[1:4]
    radius = float(sys.argv[sys.argv.index("--radius") + 1]) if "--radius" in sys.argv else 1e-3
    os.makedirs(work, exist_ok=True)
    if what == "rotation":
        p = subprocess.run([hexdem, "run", os.path.join(HERE, "rotation.toml"), "--out", work],
                           capture_output=True, text=True)
        msg = p.stderr.strip()
        print(msg)
        want = (r"rotation\.toml: \[case\] shear_model = \"rotation\" is unstable for material 'material-B' "
                r"\(id 1, plane-stress\): the Bloch analysis .*\(growth e-folding time [0-9.]+ us\); "
                r"the necessary condition k_s1 \+ 2 k_s2 = 2 sqrt\(3\) \(c66 - c12\) >= 0 fails")
        if p.returncode != 2 or len(msg.splitlines()) != 1 or not re.search(want, msg):
            sys.exit("reduced.py: expected the one-line stability refusal and exit status 2, got status %d"
                     % p.returncode)
        print("rotation model refused with the stability message (exit status 2)")
        return
    src = "fronts.toml" if what == "fronts" else "lamb.toml"
    case = variant(src, work, radius)
    run(hexdem, case, work)
    sys.exit(subprocess.run([sys.executable, os.path.join(HERE, "analyze.py"), what, case, work, "--check",
                             str(FRONT_TOL if what == "fronts" else LAMB_BOUND), "--coarse",
                             "--json", os.path.join(work, what + ".json")]).returncode)


if __name__ == "__main__":
    main()

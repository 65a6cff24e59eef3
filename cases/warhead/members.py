"""What the warhead studies (lattice_study.py, step_study.py) share: one member run with
`hexdem run` and analysed by analyse.py, and the mean and standard deviation of a group."""

import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def run_and_analyse(hexdem, case, work, threads, overrides):
    """Runs `hexdem run CASE --out WORK --threads T -q OVERRIDES...` and analyse.py on its series.

    Returns (summary, warned, None), summary the run's entry of analyse.py's JSON and warned
    whether the run completed with a warning (exit code 3), or (None, False, reason)."""
    os.makedirs(work, exist_ok=True)
    cmd = [hexdem, "run", case, "--out", work, "--threads", str(threads), "-q"] + overrides
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode not in (0, 3):  # 3: completed with a warning (analysed, and reported)
        return None, False, "hexdem run exit %d: %s" % (p.returncode, p.stderr.strip().splitlines()[-1:])
    pvd = [f for f in os.listdir(work) if f.endswith(".pvd")]
    if len(pvd) != 1:
        return None, False, "no single .pvd in %s" % work
    summary = os.path.join(work, "summary.json")
    a = subprocess.run([sys.executable, os.path.join(HERE, "analyse.py"), os.path.join(work, pvd[0]),
                        "--json", summary], capture_output=True, text=True)
    if a.returncode != 0:
        return None, False, "analyse.py exit %d: %s" % (a.returncode, a.stderr.strip())
    with open(summary) as f:
        return json.load(f)["runs"][0], p.returncode == 3, None


def mean_sd(values):
    """Mean and sample standard deviation of the values that are not None; (None, None) if none."""
    values = [v for v in values if v is not None]
    if not values:
        return None, None
    mean = sum(values) / len(values)
    sd = (sum((v - mean) ** 2 for v in values) / (len(values) - 1)) ** 0.5 if len(values) > 1 else 0.0
    return mean, sd

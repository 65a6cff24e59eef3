#!/usr/bin/python3
"""cases/warhead/damage_zones.py on the reduced warhead run (ctest case_warhead_damage_zones,
after case_warhead_reduced_run).

    test_warhead_damage_zones.py RUN_DIR

1. The run's lattice is at 0 degrees with the case's jitter (interior disks moved by up to
   0.3 r), so its bonds lie near 90 and 30 degrees from the axis, turned by at most
   asin(0.3) = 17.5 degrees: every broken bond must be counted within 20 degrees of one of
   those directions, the counts must spread over more than ten whole degrees (the jitter is
   there), and the
   directions must add up to the broken bonds of the zones (tension and shear or compression,
   back and front).
2. The zones' broken bonds, counted here independently from the frame's state and body arrays,
   equal the tool's: the disc's bonds broken in tension (state 2) and in shear or compression
   (3, 4), below and above 12 mm from the back face, leaving out the clamped rim.
3. The run breaks bonds under the nose (more than 100, as its analysis checks) and has cracking
   bonds: the figures the docs quote are not empty.
4. A folder without a series is refused with exit 2 and a one-line message that names the
   tool and the folder.
Exit 0 when all hold, 1 otherwise (one line per failure).
"""
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
WARHEAD = os.path.join(HERE, "..", "..", "cases", "warhead")
sys.path.insert(0, WARHEAD)
import analyse  # noqa: E402
import damage_zones  # noqa: E402

run = sys.argv[1]
failures = []
row, _ = damage_zones.member_zones(run)
zones = row["tension_back"] + row["tension_front"] + row["shear_back"] + row["shear_front"]
directions = row["broken_by_direction"]
if any(min(abs(d - 30), abs(d - 90)) > 20 for d in directions):
    failures.append("a 0-degree lattice has bonds within 20 degrees of 30 and 90 from the axis, got %s" % directions)
if len(directions) <= 10:
    failures.append("the jittered lattice's broken bonds lie at only %d directions: %s" % (len(directions), directions))
if sum(directions.values()) != zones:
    failures.append("directions add up to %d, the zones to %d" % (sum(directions.values()), zones))

# The same counts from the frame's arrays, written out here.
frames = analyse.read_pvd([os.path.join(run, f) for f in os.listdir(run) if f.endswith(".pvd")][0])
a = analyse.arrays(analyse.read_frame(frames[-1][1]))
x0 = a["points"][:, :2] - a["displacement"][:, :2]
i, j = a["cell_i"], a["cell_j"]
target = 0  # the outline's first body
disc = (a["body"][i] == target) & (a["body"][j] == target) & (0.5 * (x0[i, 0] + x0[j, 0]) < analyse.RIM_ZONE)
back = 0.5 * (x0[i, 1] + x0[j, 1]) < -analyse.DISC_THICKNESS + 0.012
expected = {
    "tension_back": int((disc & back & (a["state"] == 2)).sum()),
    "tension_front": int((disc & ~back & (a["state"] == 2)).sum()),
    "shear_back": int((disc & back & ((a["state"] == 3) | (a["state"] == 4))).sum()),
    "shear_front": int((disc & ~back & ((a["state"] == 3) | (a["state"] == 4))).sum()),
}
for key, value in expected.items():
    if row[key] != value:
        failures.append("%s: the tool counts %d, the frame %d" % (key, row[key], value))
if zones <= 100:
    failures.append("only %d broken bonds in the disc (the analysis checks more than 100)" % zones)
if row["cracking"] <= 0 or not np.isfinite(row["cracking_r95_mm"]):
    failures.append("no cracking bonds (%d) or no radius (%s)" % (row["cracking"], row["cracking_r95_mm"]))

empty = os.path.join(os.path.dirname(os.path.abspath(run)), "damage_zones_empty")
os.makedirs(empty, exist_ok=True)
p = subprocess.run([sys.executable, os.path.join(WARHEAD, "damage_zones.py"), empty], capture_output=True, text=True)
if (p.returncode != 2 or len(p.stderr.strip().splitlines()) != 1 or empty not in p.stderr
        or not p.stderr.startswith("damage_zones.py: ")):
    failures.append("a folder without a series: exit %d, stderr %r" % (p.returncode, p.stderr))

for f in failures:
    print("FAILED:", f)
print("damage_zones: %d failures (%d broken bonds in the zones, directions %s, %d cracking)" % (
    len(failures), zones, directions, row["cracking"]))
sys.exit(1 if failures else 0)

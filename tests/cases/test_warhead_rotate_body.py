#!/usr/bin/python3
"""lattice_study.py --rotate turns one body's lattice and leaves the other's (ctest
case_warhead_rotate_body_reduced; docs/validation.md, "Which body's lattice").

    test_warhead_rotate_body.py HEXDEM WORK_DIR

Runs cases/warhead/lattice_study.py on the reduced case (r = 1 mm, 100 m/s) at 0 and 30 degrees
for 10 us with `--rotate both`, `target` and `warhead`, and reads each member's first frame
(t = 0). Checks, per body, that its disks' positions at 30 degrees are those at 0 degrees
(to 1e-12 m, the same count) exactly when the study left that body alone, and differ (another
count, or a disk more than r/10 from where it was) when the study turned it. With `--rotate
both` both bodies turn (the study as before the option). The irregular lattice is switched
off (`mesh.jitter=0`), so that a body's disks are the lattice's sites and nothing else moves
them.

Exit 0 when all hold, 1 otherwise (one line per failure).
"""
import glob
import json
import os
import subprocess
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

HERE = os.path.dirname(os.path.abspath(__file__))
STUDY = os.path.join(HERE, "..", "..", "cases", "warhead", "lattice_study.py")
BODIES = {"target": 0, "warhead": 1}  # the outline's body order, the frames' `body` values
RADIUS = 1e-3


def first_frame(member_dir):
    frames = sorted(glob.glob(os.path.join(member_dir, "warhead_ctest", "warhead_ctest_*.vtu")))
    if not frames:
        return None
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(frames[0])
    r.Update()
    g = r.GetOutput()
    xy = vtk_to_numpy(g.GetPoints().GetData())[:, :2]
    body = vtk_to_numpy(g.GetPointData().GetArray("body"))
    return {name: xy[body == b] for name, b in BODIES.items()}


def same(a, b):
    if a.shape != b.shape:
        return False
    ia, ib = np.lexsort((a[:, 1], a[:, 0])), np.lexsort((b[:, 1], b[:, 0]))
    return bool(np.max(np.abs(a[ia] - b[ib])) <= 1e-12)


def main(argv):
    if len(argv) != 3:
        print("usage: test_warhead_rotate_body.py HEXDEM WORK_DIR", file=sys.stderr)
        return 2
    hexdem, work = argv[1], argv[2]
    failures = []
    for rotate in ("both", "target", "warhead"):
        out = os.path.join(work, rotate)
        js = out + ".json"
        cmd = [sys.executable, STUDY, hexdem, out, "--reduced", "--speeds", "100", "--radii", str(RADIUS),
               "--angles", "0", "30", "--threads", "1", "--rotate", rotate, "--set", "time.end=1e-5",
               "--set", "mesh.jitter=0", "--json", js]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            failures.append("--rotate %s: lattice_study.py exited %d: %s" % (rotate, p.returncode, p.stderr.strip()[-300:]))
            continue
        with open(js) as f:
            if json.load(f).get("rotate") != rotate:
                failures.append("--rotate %s: the JSON does not record the rotated body" % rotate)
        frames = {a: first_frame(os.path.join(out, "v100_a%d_r1_s1" % a)) for a in (0, 30)}
        if any(f is None for f in frames.values()):
            failures.append("--rotate %s: a member wrote no frame" % rotate)
            continue
        for name in BODIES:
            turned = rotate in ("both", name)
            unchanged = same(frames[0][name], frames[30][name])
            print("--rotate %-7s %-7s: %d / %d disks at 0 / 30 degrees, %s" % (
                rotate, name, len(frames[0][name]), len(frames[30][name]), "the same" if unchanged else "turned"))
            if turned and unchanged:
                failures.append("--rotate %s: the %s's lattice did not turn" % (rotate, name))
            if not turned and not unchanged:
                failures.append("--rotate %s: the %s's lattice moved, but only the %s was to turn" % (rotate, name, rotate))
    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

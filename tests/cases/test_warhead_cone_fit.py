#!/usr/bin/python3
"""cases/warhead/analyse.py's cone_fit on synthetic discs (ctest case_warhead_cone_fit).

1. A disc whose own fragment starts at r_c(z) = r0 + tan(40 deg) z: the fitted half-angle is
   40 degrees (to 0.5 degree: the bins' smallest radius lies within one disk spacing of the line).
2. The same disc with the plug moved out (no disc disk within PLUG_RADIUS of the axis): the
   cone is "formed".
3. A disc that has come apart (its own fragment has no disk in the interior depth bins, as in a
   target whose bonds all broke): no cone, with a reason, instead of a failed fit.
Exit 0 when all hold, 1 otherwise (one line per failure).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "cases", "warhead"))
import analyse  # noqa: E402


def disc(spacing, r0, angle_deg):
    """Disk centres of a square grid over the disc's section (r in [0, 0.2], z in [0, T]),
    the ones at r >= r0 + tan(angle) z in the disc's own fragment."""
    r = np.arange(spacing / 2, 0.2, spacing)
    z = np.arange(spacing / 2, analyse.DISC_THICKNESS, spacing)
    rr, zz = np.meshgrid(r, z)
    rr, zz = rr.ravel(), zz.ravel()
    pts = np.zeros((rr.size, 3))
    pts[:, 0], pts[:, 1] = rr, -zz
    a = {"points": pts, "displacement": np.zeros_like(pts)}
    own = rr >= r0 + math.tan(math.radians(angle_deg)) * zz
    return a, own


failures = []
a, own = disc(0.0005, 0.004, 40.0)
c = analyse.cone_fit(a, None, own, np.zeros(own.size, dtype=bool))
if not abs(c["half_angle_deg"] - 40.0) < 0.5:
    failures.append("cone at 40 degrees fitted at %.2f degrees" % c["half_angle_deg"])
if not c["formed"]:
    failures.append("cone at 40 degrees with its plug out not formed: %s" % c.get("reason"))
a, own = disc(0.0005, 0.0, 40.0)
own[:] = False
own[np.argmax(a["points"][:, 1])] = True  # one disk of the disc's own fragment left, in the top bin
c = analyse.cone_fit(a, None, own, np.zeros(own.size, dtype=bool))
if c["formed"] or "reason" not in c:
    failures.append("a disc that came apart gave a cone: %s" % c)
for f in failures:
    print("FAILED:", f)
print("cone_fit: %d failures" % len(failures))
sys.exit(1 if failures else 0)

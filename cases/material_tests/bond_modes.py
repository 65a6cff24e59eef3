#!/usr/bin/python3
"""How the bonds across a Brazilian disc's split opened, per bond direction (docs/validation.md,
"How the bonds across the split opened").

    /usr/bin/python3 cases/material_tests/bond_modes.py OUTDIR/brazilian.pvd [--frame K]

Reads a frame (default the last) of a run of brazilian.toml and takes the bonds of the middle
half of the disc (midpoints at |y| < D/4). The split is at x_c, the median abscissa of the
open bonds there (broken, or damage >= 0.9), as analyse.py measures it. The bonds are grouped
by the angle of their direction to the split's normal (the x axis, folded into 0-90 degrees),
and for each group the table counts, within 10 mm of x_c: the bonds that are cracking
(0 < damage < 0.9), that softened open (damage >= 0.9, not broken), that broke in tension,
shear or compression (the frame's `state`, docs/file-format.md), and all the open ones.
Directions are of the reference lattice (positions less displacements). Exit 2 when the
series cannot be read, 1 when the frame has no open bond in the middle half (the disc has not
split).
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

D = 102.70e-3  # m, the disc of brazilian.toml


def frames(pvd):
    root = ET.parse(pvd).getroot()
    base = os.path.dirname(os.path.abspath(pvd))
    return [os.path.join(base, d.get("file")) for d in root.iter("DataSet")]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("pvd")
    ap.add_argument("--frame", type=int, default=-1, help="frame index (default: the last)")
    a = ap.parse_args()
    try:
        files = frames(a.pvd)
        path = files[a.frame]
    except (OSError, ET.ParseError, IndexError) as e:
        print("bond_modes.py: %s: %s" % (a.pvd, e), file=sys.stderr)
        sys.exit(2)
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    if g.GetNumberOfCells() == 0 or g.GetCellData().GetArray("bond_damage") is None:
        print("bond_modes.py: %s: no bonds with state and bond_damage (not a hexdem frame?)" % path, file=sys.stderr)
        sys.exit(2)
    pts = vtk_to_numpy(g.GetPoints().GetData())[:, :2]
    x0 = pts - vtk_to_numpy(g.GetPointData().GetArray("displacement"))[:, :2]
    state = vtk_to_numpy(g.GetCellData().GetArray("state"))
    damage = vtk_to_numpy(g.GetCellData().GetArray("bond_damage"))
    conn = vtk_to_numpy(g.GetCells().GetConnectivityArray())
    off = vtk_to_numpy(g.GetCells().GetOffsetsArray())
    lines = np.array([c for c in range(g.GetNumberOfCells()) if g.GetCellType(c) == vtk.VTK_LINE and state[c] != 5])
    i, j = conn[off[lines]], conn[off[lines] + 1]
    s, d = state[lines], damage[lines]
    mid = 0.5 * (x0[i] + x0[j])
    middle = np.abs(mid[:, 1]) < D / 4
    is_open = (s >= 2) | (d >= 0.9)
    if not np.any(is_open & middle):
        sys.exit("bond_modes.py: %s: no open bond in the middle half: the disc has not split" % path)
    xc = float(np.median(mid[is_open & middle, 0]))
    band = middle & (np.abs(mid[:, 0] - xc) < 10e-3)
    v = x0[j] - x0[i]
    ang = np.degrees(np.arctan2(np.abs(v[:, 1]), np.abs(v[:, 0])))  # 0: along the split's normal
    print("%s: split at x = %+.2f mm; %d open bonds in the middle half" % (os.path.basename(path), xc * 1e3,
                                                                          (is_open & middle).sum()))
    print("| bond angle to the split's normal [deg] | bonds within 10 mm | cracking | softened open | broken: tension | shear | compression | open |")
    print("|---|---|---|---|---|---|---|---|")
    groups = np.round(ang[band]).astype(int)
    for a0 in sorted(set(groups)):
        sel = np.where(band)[0][groups == a0]
        ss, dd = s[sel], d[sel]
        intact = ss <= 1
        print("| %d | %d | %d | %d | %d | %d | %d | %d |" % (
            a0, len(sel), (intact & (dd > 0) & (dd < 0.9)).sum(), (intact & (dd >= 0.9)).sum(),
            (ss == 2).sum(), (ss == 3).sum(), (ss == 4).sum(), is_open[sel].sum()))

if __name__ == "__main__":
    main()

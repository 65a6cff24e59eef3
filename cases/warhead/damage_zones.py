#!/usr/bin/python3
"""Where the warhead's disc breaks, and along which bonds (docs/validation.md, "Where the
lattice angle's damage is").

    /usr/bin/python3 cases/warhead/damage_zones.py MEMBER_DIR [MEMBER_DIR ...] [--json FILE]
        [--png FILE]

Each MEMBER_DIR holds one run of the warhead case (a lattice_study.py or step_study.py member,
or `hexdem run`'s output folder): its .pvd series and energy CSV. From the last frame, for the
disc's bonds (the clamped rim, r >= 190 mm, left out):
- broken in tension, and broken in shear or compression, in the back zone (the 12 mm of the
  disc nearest its back face, where the reflected wave pulls) and in the rest of the disc;
- cracking: intact bonds with a softening damage D > 0, and the radius within which 95 % of
  them lie;
- the broken bonds by their reference direction from the axis, folded into 0-90 degrees and
  rounded to a degree: a lattice at angle a has its three bond families at |90 - a|,
  |30 - a| and 30 + a degrees from the axis (0: 90, 30, 30; 30: 60, 0, 60), so each family's
  breaks are counted apart (two families that fold onto one direction are counted together);
- the booked fracture energy at the end [J/rad].
Members whose folder names carry `_a<angle>_` (lattice_study.py's) are also grouped by angle:
mean and standard deviation of each figure. `--png` draws the bonds of the first member of
each angle: intact cracking bonds grey, tension breaks red, shear and compression breaks blue.
Exit 0, 2 on a folder that holds no run.
"""

import argparse
import glob
import json
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import analyse  # noqa: E402
from analyse import DISC_THICKNESS, RIM_ZONE, arrays, body_index, fail, read_csv, read_frame, read_pvd  # noqa: E402
from members import mean_sd  # noqa: E402

analyse.SCRIPT = "damage_zones.py"  # analyse.fail's messages name this tool

BACK_ZONE = 0.012  # m: the back zone's depth, from the back face
BROKEN_TENSION, BROKEN_SHEAR, BROKEN_COMPRESSION = 2, 3, 4  # BondState (solver/include/hexdem/solver/model.hpp)


def member_zones(folder):
    pvds = glob.glob(os.path.join(folder, "*.pvd"))
    if len(pvds) != 1:
        fail("%s: expected one .pvd series, found %d" % (folder, len(pvds)))
    frames = read_pvd(pvds[0])
    grid = read_frame(frames[-1][1])
    a = arrays(grid)
    from vtkmodules.util.numpy_support import vtk_to_numpy
    damage = grid.GetCellData().GetArray("bond_damage")
    if damage is None:
        fail("%s: the frame has no 'bond_damage' cell array" % frames[-1][1])
    damage = vtk_to_numpy(damage)
    x0 = a["points"][:, :2] - a["displacement"][:, :2]
    i, j = a["cell_i"], a["cell_j"]
    target = body_index(grid, "target")
    disc = (a["body"][i] == target) & (a["body"][j] == target)
    mid = 0.5 * (x0[i] + x0[j])
    disc &= mid[:, 0] < RIM_ZONE
    back = mid[:, 1] < -DISC_THICKNESS + BACK_ZONE
    state = a["state"]
    tension = disc & (state == BROKEN_TENSION)
    shear = disc & ((state == BROKEN_SHEAR) | (state == BROKEN_COMPRESSION))
    cracking = disc & (state < BROKEN_TENSION) & (damage > 0)
    d = x0[j] - x0[i]
    from_axis = np.degrees(np.arctan2(np.abs(d[:, 0]), np.abs(d[:, 1])))
    broken = tension | shear
    energy = read_csv(pvds[0][:-4] + ".energy.csv")
    result = {
        "folder": folder,
        "time": frames[-1][0],
        "tension_back": int((tension & back).sum()),
        "tension_front": int((tension & ~back).sum()),
        "shear_back": int((shear & back).sum()),
        "shear_front": int((shear & ~back).sum()),
        "cracking": int(cracking.sum()),
        "cracking_r95_mm": float(1e3 * np.percentile(mid[cracking, 0], 95)) if cracking.any() else 0.0,
        "fracture_J_per_rad": float(energy["fracture"][-1]),
    }
    directions, counts = np.unique(np.rint(from_axis[broken]).astype(int), return_counts=True)
    result["broken_by_direction"] = {int(k): int(c) for k, c in zip(directions, counts)}
    m = re.search(r"_a(-?[0-9.]+)_", os.path.basename(os.path.normpath(folder)))
    result["angle"] = float(m.group(1)) if m else None
    return result, (x0, i, j, cracking, tension, shear)


FIGURES = ["tension_back", "tension_front", "shear_back", "shear_front", "cracking", "cracking_r95_mm",
           "fracture_J_per_rad"]


def directions_text(by_direction):
    """'90: 561, 30: 1020': broken bonds per direction from the axis [deg], largest first."""
    return ", ".join("%d: %d" % (d, c) for d, c in sorted(by_direction.items(), key=lambda x: -x[1]))


def draw(png, maps):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    fig, axes = plt.subplots(len(maps), 1, figsize=(10, 2.9 * len(maps)), squeeze=False)
    for ax, (title, (x0, i, j, cracking, tension, shear)) in zip(axes[:, 0], maps):
        for sel, colour in ((cracking, "0.75"), (tension, "tab:red"), (shear, "tab:blue")):
            ax.add_collection(LineCollection(1e3 * np.stack([x0[i[sel]], x0[j[sel]]], axis=1), colors=colour,
                                             linewidths=0.6))
        ax.set_xlim(0, 120)
        ax.set_ylim(-1e3 * DISC_THICKNESS - 1, 1)
        ax.set_aspect("equal")
        ax.set_title(title, fontsize=9)
        ax.set_ylabel("z [mm]")
    axes[-1, 0].set_xlabel("r [mm] (grey: cracking, red: broken in tension, blue: in shear or compression)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("members", nargs="+")
    p.add_argument("--json")
    p.add_argument("--png")
    args = p.parse_args(argv)
    rows, maps = [], {}
    for folder in args.members:
        if not os.path.isdir(folder):
            fail("%s: not a folder" % folder)
        row, drawn = member_zones(folder)
        rows.append(row)
        key = row["angle"]
        if key not in maps:
            maps[key] = ("%s, angle %s: %d tension, %d shear or compression breaks, %d cracking" % (
                os.path.basename(os.path.normpath(folder)), "?" if key is None else "%g" % key,
                row["tension_back"] + row["tension_front"], row["shear_back"] + row["shear_front"],
                row["cracking"]), drawn)
    print("| member | " + " | ".join(FIGURES) + " | broken by direction from the axis [deg: bonds] |")
    print("|---" * (len(FIGURES) + 2) + "|")
    for r in rows:
        print("| %s | " % os.path.basename(os.path.normpath(r["folder"])) +
              " | ".join(("%.3f" % r[f]) if isinstance(r[f], float) else str(r[f]) for f in FIGURES) +
              " | %s |" % directions_text(r["broken_by_direction"]))
    groups = {}
    for r in rows:
        if r["angle"] is not None:
            groups.setdefault(r["angle"], []).append(r)
    summary = {}
    if groups:
        print("\nPer angle: mean, standard deviation\n")
        print("| angle | members | " + " | ".join(FIGURES) + " | broken by direction from the axis (mean) |")
        print("|---" * (len(FIGURES) + 3) + "|")
        for angle in sorted(groups):
            g = groups[angle]
            stats = {f: mean_sd([r[f] for r in g]) for f in FIGURES}
            summary["%g" % angle] = {f: {"mean": s[0], "sd": s[1]} for f, s in stats.items()}
            directions = sorted({d for r in g for d in r["broken_by_direction"]})
            mean_dir = {d: sum(r["broken_by_direction"].get(d, 0) for r in g) / len(g) for d in directions}
            summary["%g" % angle]["broken_by_direction"] = mean_dir
            print("| %g | %d | " % (angle, len(g)) +
                  " | ".join("%.3g, %.2g" % s if len(g) > 1 else "%.3g" % s[0] for s in stats.values()) +
                  " | %s |" % directions_text({d: round(c) for d, c in mean_dir.items()}))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"members": rows, "angles": summary}, f, indent=1)
    if args.png:
        draw(args.png, [maps[k] for k in sorted(maps, key=lambda a: (a is None, a if a is not None else 0))])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

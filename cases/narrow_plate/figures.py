#!/usr/bin/env python3
"""Figures and error numbers of the narrow-plate case: sigma_y along the plate at t = 104 us,
the lattice (disks on the axis and the width average of each lattice row) against 1D bar
theory and, when given, the CalculiX solution (calculix.py); and the sigma_y field of the
lattice beside the finite-element one (the paper's Fig. 7).

    /usr/bin/python3 cases/narrow_plate/figures.py RUN_DIR [--fe FE_DIR] [--out DIR]
        [--case CASE.toml]

RUN_DIR is the --out folder of `hexdem run` (with narrow_plate.pvd), FE_DIR the folder of
calculix.py. Writes DIR/narrow_plate_sigma_y.png, DIR/narrow_plate_field.png (with --fe) and
DIR/narrow_plate_errors.json (default DIR: RUN_DIR), and prints the L2 relative errors.
Needs the vtk (ParaView's) and matplotlib modules of /usr/bin/python3.
"""

import argparse
import json
import os
import sys

import numpy as np

sys.dont_write_bytecode = True  # no __pycache__ in the source tree (the ctest imports these)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from run_status import require_completed  # noqa: E402

import plate as pl  # noqa: E402

SCRIPT = "figures.py"


def read_field_csv(path):
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return data[:, 0], data[:, 1], data[:, 2]


def errors(plate, t, lattice, fe):
    """The L2 relative errors of every profile against bar theory and of the lattice's against
    the FE ones (at the lattice's points)."""
    out = {"time": t, "bar_speed": plate.bar_speed}
    for key, p in lattice.items():
        out["lattice_%s_vs_bar" % key] = p.l2_against_bar(plate, t)
    for key, p in fe.items():
        out["fe_%s_vs_bar" % key] = p.l2_against_bar(plate, t)
        out["lattice_%s_vs_fe_%s" % (key, key)] = lattice[key].l2_against(p)
    return out


def plot_profiles(path, plate, t, lattice, fe, numbers):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, dax) = plt.subplots(2, 1, figsize=(9, 7), sharex=True,
                                  gridspec_kw={"height_ratios": [3, 2]})
    depth = np.linspace(0.0, plate.length, 3001)
    bar = plate.bar_sigma_y(depth, t)
    mm, mpa = 1e3, 1e-6
    ax.plot(depth * mm, bar * mpa, "k-", lw=1.2,
            label="1D bar theory, c = %.0f m/s" % plate.bar_speed)
    styles = {"axis": dict(ls="", marker="o", ms=3, color="tab:blue"),
              "mean": dict(ls="-", lw=1.0, color="tab:cyan")}
    fe_styles = {"axis": dict(ls="--", lw=1.0, color="tab:red"),
                 "mean": dict(ls=":", lw=1.4, color="tab:orange")}
    for key, p in lattice.items():
        ax.plot(p.depth * mm, p.sigma_y * mpa, label="%s (L2 %.2f %%)"
                % (p.label, 100 * numbers["lattice_%s_vs_bar" % key]), **styles[key])
        dax.plot(p.depth * mm, (p.sigma_y - plate.bar_sigma_y(p.depth, t)) / plate.q0 * 100,
                 label=p.label, **styles[key])
    for key, p in fe.items():
        ax.plot(p.depth * mm, p.sigma_y * mpa, label="CalculiX %s (L2 %.2f %%)"
                % (p.label[4:], 100 * numbers["fe_%s_vs_bar" % key]), **fe_styles[key])
        dax.plot(p.depth * mm, (p.sigma_y - plate.bar_sigma_y(p.depth, t)) / plate.q0 * 100,
                 label="CalculiX %s" % p.label[4:], **fe_styles[key])
    ax.set_ylabel("sigma_y [MPa]")
    title = "Narrow plate, Eq. 23 ramp: sigma_y along the plate at t = %.0f us" % (t * 1e6)
    if fe:
        title += "\nL2 lattice vs CalculiX: axis %.2f %%, width average %.2f %%" % (
            100 * numbers["lattice_axis_vs_fe_axis"], 100 * numbers["lattice_mean_vs_fe_mean"])
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, alpha=0.3)
    dax.axhline(0.0, color="k", lw=0.8)
    dax.set_xlabel("distance from the loaded end, -y [mm]")
    dax.set_ylabel("(sigma_y - bar theory) / q0 [%]")
    dax.grid(True, alpha=0.3)
    dax.legend(fontsize=8, loc="lower right", ncol=2)
    dax.set_xlim(0.0, plate.length * mm)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_fields(path, plate, t, vtu, fe_field):
    """The lattice's disks at their true size coloured by sigma_y, above the FE elements, both
    mirrored about the symmetry plane to the full plate width, the plate lying horizontally."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import EllipseCollection
    _, x0, y0, syy, _ = pl.read_frame(SCRIPT, vtu)
    mm, mpa = 1e3, 1e-6
    vmin, vmax = -plate.q0 * mpa, 0.0
    panels = 2 if fe_field is not None else 1
    fig, axes = plt.subplots(panels, 1, figsize=(13, 0.6 + 1.15 * panels), squeeze=False,
                             layout="constrained")
    w = plate.half_width * mm
    ax = axes[0][0]
    xs = np.concatenate([-y0, -y0]) * mm            # horizontal: distance from the loaded end
    ys = np.concatenate([x0, -x0]) * mm             # vertical: across the full width
    vals = np.concatenate([syy, syy]) * mpa
    d = 2 * plate.radius * mm
    disks = EllipseCollection(np.full(xs.size, d), np.full(xs.size, d), np.zeros(xs.size),
                              units="xy", offsets=np.column_stack([xs, ys]),
                              offset_transform=ax.transData, cmap="turbo")
    disks.set_array(vals)
    disks.set_clim(vmin, vmax)
    ax.add_collection(disks)
    ax.set_title("hexdem lattice (%d disks in the half model), t = %.0f us" % (x0.size, t * 1e6),
                 fontsize=9)
    if fe_field is not None:
        fx, fy, fs = fe_field
        size = fx.min() * 2
        nx, ny = int(round(plate.half_width / size)), int(round(plate.length / size))
        grid = fs.reshape(ny, nx) * mpa                      # rows j (y = -(j + 1/2) size)
        full = np.concatenate([grid[:, ::-1], grid], axis=1)  # x from -W to W
        fax = axes[1][0]
        fax.imshow(full.T, extent=(0, plate.length * mm, -w, w), origin="lower", aspect="equal",
                   cmap="turbo", vmin=vmin, vmax=vmax, interpolation="nearest")
        fax.set_title("CalculiX, %d elements of %.3g mm in the half model" % (fs.size, size * mm),
                      fontsize=9)
    for row in axes:
        a = row[0]
        a.set_xlim(0, plate.length * mm)
        a.set_ylim(-w - 1, w + 1)
        a.set_aspect("equal")
        a.set_ylabel("x [mm]")
    axes[-1][0].set_xlabel("distance from the loaded end, -y [mm]")
    fig.colorbar(disks, ax=[r[0] for r in axes], label="sigma_y [MPa]", aspect=10, pad=0.01)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv):
    parser = argparse.ArgumentParser(description="Figures and errors of the narrow-plate case.")
    parser.add_argument("run_dir", help="the --out folder of hexdem run (narrow_plate.pvd)")
    parser.add_argument("--fe", help="the output folder of calculix.py")
    parser.add_argument("--out", help="folder for the figures (default: RUN_DIR)")
    parser.add_argument("--case", default=pl.CASE_FILE, help="case file (this folder's case.toml)")
    args = parser.parse_args(argv)
    plate = pl.load_plate(SCRIPT, args.case)
    out = args.out or args.run_dir
    if not os.path.isdir(out):
        pl.fail(SCRIPT, "output folder '%s' does not exist" % out)
    series = os.path.join(args.run_dir, "narrow_plate.pvd")
    if not os.path.isfile(series):
        pl.fail(SCRIPT, "%s: no such file (run the case first)" % series)
    require_completed(series, SCRIPT)
    vtu, t = pl.frame_at(SCRIPT, series, plate.t_end)
    if abs(t - plate.t_end) > 1e-3 * plate.t_end:
        pl.fail(SCRIPT, "%s: no frame at t = %g s (nearest %g s)" % (series, plate.t_end, t))
    t, axis, mean = pl.lattice_profiles(SCRIPT, vtu, plate.radius)
    lattice = {"axis": axis, "mean": mean}
    fe, fe_field = {}, None
    if args.fe:
        profiles = pl.read_profiles_csv(SCRIPT, os.path.join(args.fe, "narrow_plate_fe.csv"))
        fe = {"axis": profiles["FE, axis column"], "mean": profiles["FE, width average"]}
        field = os.path.join(args.fe, "narrow_plate_fe_field.csv")
        if os.path.isfile(field):
            fe_field = read_field_csv(field)
    numbers = errors(plate, t, lattice, fe)
    with open(os.path.join(out, "narrow_plate_errors.json"), "w") as f:
        json.dump(numbers, f, indent=1)
    print("sigma_y at t = %.4g us, L2 relative errors:" % (t * 1e6))
    for key, value in numbers.items():
        if key not in ("time", "bar_speed"):
            print("  %-34s %.4f" % (key, value))
    plot_profiles(os.path.join(out, "narrow_plate_sigma_y.png"), plate, t, lattice, fe, numbers)
    print("figure: %s" % os.path.join(out, "narrow_plate_sigma_y.png"))
    plot_fields(os.path.join(out, "narrow_plate_field.png"), plate, t, vtu, fe_field)
    print("figure: %s" % os.path.join(out, "narrow_plate_field.png"))


if __name__ == "__main__":
    main(sys.argv[1:])

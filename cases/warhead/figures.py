"""Figures of the warhead case (paper Figs. 10-12) from finished runs and the numbers of
analyse.py:

    scripts/pvbatch-xvfb.sh cases/warhead/figures.py OUT/warhead_summary.json OUT \
        [--plugin PATH] [--zoom X0 Y0 X1 Y1]

writes into OUT

- warhead_<case>_cracks_matched.png, warhead_<case>_cracks_end.png, warhead_<case>_fragments_end.png:
  crack maps (disks shaded by damage, cracks coloured by mode) at the frame where the nose
  tip is nearest to the common penetration depth, and crack map and fragments at the end;
- warhead_damage_forms.png: those panels side by side, one row per impact velocity;
- warhead_velocity.png: the warhead's mass-averaged axial velocity and its nose depth against
  time, all runs in one plot.

The panels come from vtkfilters/scripts/figure_cracks.py and figure_fragments.py (the HexDEM
Crack Map and Fragment Counter filters).
"""

import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(REPO, "vtkfilters", "scripts"))

import figure_common as fc  # noqa: E402
import figure_cracks  # noqa: E402
import figure_fragments  # noqa: E402

SCRIPT = "warhead figures.py"
ZOOM = (0.0, -0.06, 0.07, 0.03)  # m: r from the axis, z from below the disc to above the warhead


def main(argv):
    parser = argparse.ArgumentParser(description="Figures of the warhead case.")
    parser.add_argument("summary", help="JSON written by analyse.py --json")
    parser.add_argument("out", help="folder for the PNGs")
    parser.add_argument("--plugin", help="path of HexDEMFilters.so")
    parser.add_argument("--zoom", nargs=4, type=float, default=ZOOM,
                        metavar=("X0", "Y0", "X1", "Y1"), help="box shown [m] (default %s)" % (ZOOM,))
    args = parser.parse_args(argv)
    if not os.path.isfile(args.summary):
        fc.fail(SCRIPT, "'%s' does not exist (run analyse.py --json first)" % args.summary)
    if not os.path.isdir(args.out):
        fc.fail(SCRIPT, "output folder '%s' does not exist" % args.out)
    try:
        with open(args.summary) as f:
            summary = json.load(f)
        runs = summary["runs"]
        depth = summary["matching_depth_m"]
    except (ValueError, KeyError) as e:
        fc.fail(SCRIPT, "'%s' is not a summary of analyse.py (%s)" % (args.summary, e))

    from paraview import simple as pv
    fc.load_plugin(SCRIPT, pv, args.plugin)
    zoom = ["%.6g" % v for v in args.zoom]
    size = ["900", "1000"]
    panels = []
    for r in runs:
        series, case = r["series"], r["case"]
        v0 = r["impact_velocity_m_s"]
        t_match = r["matching_frame"]["time_s"]
        t_end = r["end_time_s"]
        files = [os.path.join(args.out, "%s_cracks_matched.png" % case),
                 os.path.join(args.out, "%s_cracks_end.png" % case),
                 os.path.join(args.out, "%s_fragments_end.png" % case)]
        common = ["--zoom"] + zoom + ["--size"] + size
        figure_cracks.main([series, files[0], "--time", repr(t_match), "--disks", "damage",
                            "--title", "%.0f m/s: cracks at nose depth %.1f mm (t = %.0f us)" % (
                                v0, 1e3 * r["matching_frame"]["frame_depth_m"], 1e6 * t_match)] + common)
        figure_cracks.main([series, files[1], "--time", repr(t_end), "--disks", "damage",
                            "--title", "%.0f m/s: cracks at t = %.0f us" % (v0, 1e6 * t_end)] + common)
        figure_fragments.main([series, files[2], "--time", repr(t_end), "--min-disks", "2",
                               "--title", "%.0f m/s: fragments at t = %.0f us" % (v0, 1e6 * t_end)] + common)
        panels.append((v0, files))
        for p in files:
            print("figure: %s" % p)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(panels), 3, figsize=(13.5, 5.0 * len(panels)), squeeze=False)
    for row, (v0, files) in enumerate(panels):
        for col, path in enumerate(files):
            axes[row][col].imshow(mpimg.imread(path))
            axes[row][col].axis("off")
    fig.suptitle("Steel warhead into a concrete disc (axisymmetric; r to the right, z up): crack maps "
                 "at a common nose depth of %.1f mm, and at the end" % (1e3 * depth))
    fig.tight_layout()
    forms = os.path.join(args.out, "warhead_damage_forms.png")
    fig.savefig(forms, dpi=100)
    plt.close(fig)
    print("figure: %s" % forms)

    fig, (ax_v, ax_d) = plt.subplots(2, 1, figsize=(8, 8), sharex=True)
    for r in runs:
        h = r["history"]
        t = [1e6 * x for x in h["time_s"]]
        label = "%.0f m/s (%s, %+.1f m/s)" % (r["impact_velocity_m_s"], r["outcome"],
                                              r["residual_velocity_m_s"])
        ax_v.plot(t, h["warhead_vz_m_s"], label=label)
        ax_d.plot(t, [1e3 * x for x in h["depth_m"]], label="%.0f m/s" % r["impact_velocity_m_s"])
    ax_v.axhline(0.0, color="0.6", lw=0.8)
    ax_v.set_ylabel("warhead velocity v_z [m/s] (mass average)")
    ax_v.legend()
    ax_v.grid(alpha=0.3)
    ax_d.axhline(0.0, color="0.6", lw=0.8)
    ax_d.axhline(depth * 1e3, color="0.6", lw=0.8, ls="--")
    ax_d.set_ylabel("nose depth below the top face [mm]")
    ax_d.set_xlabel("time [us]")
    ax_d.grid(alpha=0.3)
    ax_d.legend()
    fig.suptitle("Warhead velocity and penetration (dashed: common depth of the crack maps)")
    fig.tight_layout()
    velocity = os.path.join(args.out, "warhead_velocity.png")
    fig.savefig(velocity, dpi=100)
    plt.close(fig)
    print("figure: %s" % velocity)


if __name__ == "__main__":
    main(sys.argv[1:])

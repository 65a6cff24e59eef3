#!/usr/bin/env python3
"""Figure of the virtual material tests (cases/material_tests/README.md).

    figures.py OUT.png --tension T.json --brazilian B.json [--brazilian-reference BFE.json]
               --beam BEAM.json [BEAM2.json ...] [--beam-reference FC.json [FC2.json ...]]

T.json and B.json are `run_study.py --json` files of the angle studies, BEAM*.json those of
notched-beam runs (one curve per run). Top left: the tension test's stress-displacement curves
at every lattice angle; top right: the Brazilian discs' splitting stress 2P/(pi D t) against
time, with the stresses of `brazilian_fe.py --json BFE.json` at which its crack starts and at
which its cohesive zone spans the middle half of the diameter; bottom left: the discs' open
bonds (broken, or D > 0.9) when their crack spans the middle half of the loaded diameter, one
colour per angle; bottom right: the notched beam's load-deflection curves, with the
fictitious-crack finite-element curves of `fictitious_crack.py --json FC.json` when given.
"""
import argparse
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--tension", required=True)
    ap.add_argument("--brazilian", required=True)
    ap.add_argument("--brazilian-reference", help="brazilian_fe.py --json file")
    ap.add_argument("--beam", nargs="+", required=True)
    ap.add_argument("--beam-reference", nargs="+", default=[], help="fictitious_crack.py --json files")
    a = ap.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from analyse import last_frame  # noqa: E402

    fig, axes = plt.subplots(2, 2, figsize=(13, 10))
    ax_tension, ax_curves = axes[0]
    ax_splits, ax_beam = axes[1]
    tension = json.load(open(a.tension))["runs"]
    for r in sorted(tension, key=lambda r: r["angle"]):
        c = r["curve"]
        ax_tension.plot(c["displacement_um"], c["stress_MPa"], label="%g deg: %.2f MPa" % (r["angle"], r["peak_stress_MPa"]))
    ax_tension.set_xlabel("grip displacement [um]")
    ax_tension.set_ylabel("nominal stress [MPa]")
    ax_tension.set_title("uniaxial tension, lattice angles 0-30 deg")
    ax_tension.legend()

    brazilian = json.load(open(a.brazilian))["runs"]
    study_dir = os.path.dirname(os.path.abspath(a.brazilian))
    for r in sorted(brazilian, key=lambda r: r["angle"]):
        # The study's folder of the run: a<angle>, with _r<radius> when the study had --radii.
        tags = ["a%g" % r["angle"], "a%g_r%g" % (r["angle"], r["radius"])]
        found = [p for p in (os.path.join(study_dir, "brazilian", t, "brazilian.pvd") for t in tags)
                 if os.path.isfile(p)]
        if not found:
            sys.exit("figures.py: %s: no series of the %g-degree run under %s (looked for %s)"
                     % (a.brazilian, r["angle"], os.path.join(study_dir, "brazilian"), ", ".join(tags)))
        pvd = found[0]
        if np.isfinite(r["split_span_time"]):
            f = last_frame(pvd, r["split_span_time"])
            mid = f["mid"][f["opened"]]
            ax_splits.scatter(mid[:, 0] * 1e3, mid[:, 1] * 1e3, s=3, label="%g deg, %.2f ms: split at %.2f MPa"
                          % (r["angle"], f["time"] * 1e3, r["split_strength_MPa"]))
        c = r["curve"]
        ax_curves.plot(c["time_ms"], c["stress_MPa"], label="%g deg: split %.2f MPa, largest %.2f MPa"
                   % (r["angle"], r["split_strength_MPa"], r["peak_strength_MPa"]))
    t = np.linspace(0, 2 * np.pi, 200)
    ax_splits.plot(51.3 * np.cos(t), 51.3 * np.sin(t), color="0.6", lw=0.8)
    ax_splits.set_aspect("equal")
    ax_splits.set_xlabel("x [mm]")
    ax_splits.set_ylabel("y [mm]")
    ax_splits.set_title("Brazilian disc: open bonds when the crack spans the middle half")
    ax_splits.legend(fontsize=8, loc="lower right")
    if a.brazilian_reference:
        ref = json.load(open(a.brazilian_reference))
        ax_curves.axhline(ref["initiation_MPa"], color="k", ls="--", lw=1,
                      label="fictitious crack FE: crack starts, %.2f MPa" % ref["initiation_MPa"])
        ax_curves.axhline(ref["quarter_span_MPa"], color="k", ls=":", lw=1,
                      label="FE: cohesive zone spans the middle half, %.2f MPa" % ref["quarter_span_MPa"])
    ax_curves.set_xlim(0.6, 1.6)
    ax_curves.set_ylim(0, 4.6)
    ax_curves.set_xlabel("time [ms]")
    ax_curves.set_ylabel("2P / (pi D t) [MPa]")
    ax_curves.set_title("Brazilian disc: splitting stress, lattice angles 0-30 deg")
    ax_curves.legend(fontsize=8, loc="lower left")

    for path in a.beam:
        for r in json.load(open(path))["runs"]:
            c = r["curve"]
            ax_beam.plot(c["deflection_mm"], c["load_N"],
                       label="r = %g mm: peak %.0f N, W/A %.0f J/m^2" % (r["radius"] * 1e3, r["peak_load_N"],
                                                                       r["work_of_fracture_J_m2"]))
    for path, style in zip(a.beam_reference, ("k--", "k:", "k-.")):
        ref = json.load(open(path))
        sup = "hinged supports (as the case)" if ref["supports"] == "point" else "20 mm held support strips"
        if ref.get("strip") == "contact":
            sup += ", a loading plate that only pushes"
        ax_beam.plot([p["deflection_mm"] for p in ref["points"]], [p["load_N"] for p in ref["points"]], style, lw=1.5,
                   label="fictitious crack FE, %s: peak %.0f N" % (sup, ref["peak_load_N"]))
    ax_beam.set_xlabel("deflection [mm]")
    ax_beam.set_ylabel("load [N]")
    ax_beam.set_title("notched beam (Petersson), G_F = 124 J/m^2")
    ax_beam.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print(a.out)


if __name__ == "__main__":
    main(sys.argv[1:])

#!/usr/bin/env python3
"""Analyses a virtual material test of cases/material_tests/ (README.md there).

    analyse.py KIND OUTDIR/CASE.pvd [--json FILE] [--check]

KIND is tension, compression, brazilian or notched_beam. Reads the run's reactions, energy and
probe CSVs and its last frame, and prints one line of results:
  tension       peak stress = max reaction of the grip / (waist width 30 mm x t)
  compression   peak stress = max |reaction| of the platen / (waist width 30 mm x t)
  brazilian     split strength 2 P / (pi D t) with P the largest load before the crack
                spans the middle half of the loaded diameter (open bonds, broken or D > 0.9,
                in every band of 4r height of |y| < D/4), D the rim's diameter; the largest
                load of the run as peak strength; the crack's distance from the loaded
                diameter (the median abscissa of the open bonds in the middle half of the
                disc, when the load has fallen to 70 % of its peak); checks that the disc
                split within the run (else the peak is only a lower bound) and that the
                crack spanned the middle half before
  notched_beam  peak load, deflection at the peak, work of fracture W / (t x ligament)
                (RILEM TC 50), facet length (2r / sqrt 3 per bond) of the cracked bonds
                (broken or D > 0.5: the crack and its process zone) and of the open ones
                (broken or D > 0.9: the crack), at the end of the run
and for all: max |energy error| and the kinetic / elastic energy ratio at 90 % of the peak.
With --check, exits 1 when a check of the kind fails (limits below); a run that did not
complete (see run_status.py) is refused with exit 2.
"""
import argparse
import csv
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from run_status import require_completed  # noqa: E402

SCRIPT = "analyse.py"
GAUGE_WIDTH = 0.030    # m, tension dog-bone
PRISM_WIDTH = 0.030    # m, compression specimen: the waist
LIGAMENT = 0.1009      # m, notched beam: depth 200.92 mm - notch 100 mm


def fail(message, code=2):
    sys.stderr.write("%s: %s\n" % (SCRIPT, message))
    sys.exit(code)


def read_csv(path):
    if not os.path.isfile(path):
        fail("%s: no such file" % path)
    with open(path) as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        fail("%s: no data rows" % path)
    data = np.array([[float(v) for v in r] for r in rows[1:]])
    return {name: data[:, k] for k, name in enumerate(rows[0])}


def series(pvd):
    """The frames of a .pvd series as (time, file), in time order."""
    root = ET.parse(pvd).getroot()
    base = os.path.dirname(os.path.abspath(pvd))
    frames = sorted((float(d.get("timestep")), os.path.join(base, d.get("file"))) for d in root.iter("DataSet"))
    if not frames:
        fail("%s: the series has no frames" % pvd)
    return frames


def last_frame(pvd, at=None):
    """The last frame, or the first at or after time `at`."""
    frames = series(pvd)
    if at is not None:
        later = [f for f in frames if f[0] >= at]
        frames = later[:1] if later else frames
    return read_frame(*frames[-1])


def read_frame(time, path):
    """One frame's bonds (midpoints in the reference state, cracked and open flags)."""
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    g = reader.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData())
    cd = g.GetCellData()
    conn = vtk_to_numpy(g.GetCells().GetConnectivityArray())
    state = vtk_to_numpy(cd.GetArray("state"))
    damage = vtk_to_numpy(cd.GetArray("bond_damage")) if cd.GetArray("bond_damage") else np.zeros(len(state))
    radius = vtk_to_numpy(g.GetPointData().GetArray("radius"))
    ci, cj = conn[0::2], conn[1::2]
    bond = state < 5  # state 5: a contact between bodies, not a bond
    cracked = bond & ((state >= 2) | (damage > 0.5))
    opened = bond & ((state == 2) | (damage > 0.9))
    disp = vtk_to_numpy(g.GetPointData().GetArray("displacement"))
    ref = pts - disp
    return {"mid": 0.5 * (ref[ci] + ref[cj]), "cracked": cracked, "opened": opened,
            "r": float(np.median(radius)), "ref": ref, "time": time}


def disc_diameter(case, path):
    """The diameter of the disc's rim [m]: twice the radius of its first arc segment."""
    units = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "in": 0.0254, "ft": 0.3048}
    scale = case.get("scale", units.get(case.get("units", "m")))
    for body in case.get("body", []):
        for shape in body.get("shape", []):
            for seg in shape.get("segments", []):
                if "center" in seg and scale:
                    return 2.0 * math.hypot(seg["to"][0] - seg["center"][0], seg["to"][1] - seg["center"][1]) * scale
    fail("%s: the disc's outline has no arc segment (a segment with a center) to take its diameter from" % path)


def spans_middle(frame, D):
    """Whether the open bonds cover the middle half of the loaded diameter (|y| < D/4) in every
    band of 4r height."""
    mid, r = frame["mid"], frame["r"]
    y = mid[frame["opened"] & (np.abs(mid[:, 1]) < 0.25 * D), 1]
    bands = max(1, int(round(0.5 * D / (4.0 * r))))
    return bool(np.all(np.histogram(y, np.linspace(-0.25 * D, 0.25 * D, bands + 1))[0] > 0))


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("kind", choices=["tension", "compression", "brazilian", "notched_beam"])
    ap.add_argument("pvd")
    ap.add_argument("--json")
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args(argv)
    warning = require_completed(a.pvd, SCRIPT)  # a run that warned is analysed and marked
    stem = os.path.splitext(a.pvd)[0]
    case_toml = stem + ".case.toml"
    import tomllib
    with open(case_toml, "rb") as f:
        case = tomllib.load(f)
    t = case["case"]["thickness"]
    reactions = read_csv(stem + ".reactions.csv")
    energy = read_csv(stem + ".energy.csv")
    frame = last_frame(a.pvd)
    time = reactions["time"]
    out = {"kind": a.kind, "run_warning": warning or None,
           "angle": case["mesh"].get("angle", 0.0), "radius": case["mesh"]["radius"],
           "seed": case.get("random", {}).get("seed"),
           "max_energy_error": float(np.max(np.abs(energy["relative_error"])))}
    checks = []
    if a.kind in ("tension", "compression"):
        col = "grip.fy" if a.kind == "tension" else "platen.fy"
        force = reactions[col] if a.kind == "tension" else -reactions[col]
        k = int(np.argmax(force))
        width = GAUGE_WIDTH if a.kind == "tension" else PRISM_WIDTH
        out["peak_stress_MPa"] = float(force[k] / (width * t) / 1e6)
        out["peak_time"] = float(time[k])
        # Quasi-static loading: the kinetic energy against the elastic one where the force first
        # reaches 90 % of its peak (at the peak itself the first cracks are dynamic events).
        k90 = int(np.nonzero(force >= 0.9 * force[k])[0][0])
        e90 = np.interp(time[k90], energy["time"], energy["elastic"])
        out["kinetic_over_elastic_at_peak"] = float(np.interp(time[k90], energy["time"], energy["kinetic"]) / e90)
        out["fracture_energy_J"] = float(energy["fracture"][-1])
        # The stress-displacement curve: the grip's (platen's) displacement from its imposed
        # velocity (the ramp of the case's table function) against the nominal stress.
        grip = case["boundary"][1]
        pts = np.array(grip["function"]["points"])
        f_t = np.interp(time, pts[:, 0], pts[:, 1])
        disp = abs(grip["vy"]) * np.concatenate([[0.0], np.cumsum(0.5 * (f_t[1:] + f_t[:-1]) * np.diff(time))])
        step = max(1, len(time) // 200)
        out["curve"] = {"displacement_um": [float(v * 1e6) for v in disp[::step]],
                        "stress_MPa": [float(v / (width * t) / 1e6) for v in force[::step]]}
        checks.append(("post-peak force below 60 % of the peak", force[-1] < 0.6 * force[k]))
        checks.append(("kinetic energy below 1 % of the elastic at 90 % of the peak", out["kinetic_over_elastic_at_peak"] < 0.01))
    elif a.kind == "brazilian":
        force = -reactions["top.fy"]
        k = int(np.argmax(force))
        # The split: the first frame after the load has fallen to 70 % of its peak, the bonds
        # there that are open (broken, or D > 0.9) in the middle half of the disc's height.
        drop = np.nonzero((np.arange(len(force)) > k) & (force < 0.7 * force[k]))[0]
        # A disc that has not split by the end of the run has no split strength: its largest
        # load is only a lower bound (the check below fails, and --strict fails the study).
        out["split"] = bool(len(drop))
        checks.append(("the disc split within the run (the load fell below 70 % of its peak)", len(drop) > 0))
        D = disc_diameter(case, case_toml)
        nominal = 2.0 / (math.pi * D * t) / 1e6
        out["peak_strength_MPa"] = float(force[k] * nominal)
        # The split: the first frame on which the open crack spans the middle half of the loaded
        # diameter. The split strength is the largest load up to it. The largest load of the run
        # can come later: a disc whose crack has formed may carry more load until the wedges
        # under its flats fail (brazilian_fe.py: with one cohesive crack and an elastic rest the
        # load rises all the way), and that second mechanism is not the split.
        # The frames searched: from the load's first half of its peak to the split's frame (the
        # first frame after the load has fallen to 70 % of its peak).
        frame = last_frame(a.pvd, time[drop[0]] if len(drop) else None)
        out["split_frame_time"] = frame["time"]
        start = time[int(np.nonzero(force >= 0.5 * force[k])[0][0])]
        span = next((f for f in (read_frame(*tf) for tf in series(a.pvd) if start <= tf[0] <= frame["time"])
                     if spans_middle(f, D)), None)
        checks.append(("the crack spans the middle half of the loaded diameter by the split", span is not None))
        out["split_strength_MPa"] = float(np.max(force[time <= span["time"]]) * nominal) if span else float("nan")
        out["split_span_time"] = span["time"] if span else float("nan")
        step = max(1, len(time) // 400)
        out["curve"] = {"time_ms": [float(v * 1e3) for v in time[::step]],
                        "stress_MPa": [float(v * nominal) for v in force[::step]]}
        mid = frame["mid"]
        middle = frame["opened"] & (np.abs(mid[:, 1]) < 0.25 * D)
        out["crack_bonds_middle"] = int(middle.sum())
        # The crack's position: the median abscissa of those bonds (the loaded diameter is x = 0).
        out["crack_offset_mm"] = float(abs(np.median(mid[middle, 0])) * 1e3) if middle.any() else float("nan")
        out["crack_offset_in_r"] = out["crack_offset_mm"] / (frame["r"] * 1e3)
        checks.append(("the crack runs along the loaded diameter, within 2r", middle.any() and out["crack_offset_in_r"] <= 2.0))
    else:
        force = -reactions["load.fy"]
        probes = read_csv(stem + ".probes.csv")
        defl = -np.interp(time, probes["time"], probes["load_point.displacement_y"])
        k = int(np.argmax(force))
        out["peak_load_N"] = float(force[k])
        out["deflection_at_peak_mm"] = float(defl[k] * 1e3)
        work = float(np.trapz(force, defl))
        out["work_J"] = work
        out["work_of_fracture_J_m2"] = work / (t * LIGAMENT)
        out["final_load_over_peak"] = float(force[-1] / force[k])
        # The dissipation the ledger books (fracture energy of the run) over the ligament: the
        # work of fracture without what the beam still stores when the run ends.
        out["fracture_energy_over_ligament_J_m2"] = float(energy["fracture"][-1] / (t * LIGAMENT))
        out["elastic_at_end_J"] = float(energy["elastic"][-1])
        r = frame["r"]
        out["broken_facet_length_mm"] = float(frame["cracked"].sum() * 2 * r / math.sqrt(3) * 1e3)
        out["open_facet_length_mm"] = float(frame["opened"].sum() * 2 * r / math.sqrt(3) * 1e3)
        out["curve"] = {"deflection_mm": [float(v * 1e3) for v in defl[::max(1, len(defl) // 200)]],
                        "load_N": [float(v) for v in force[::max(1, len(force) // 200)]]}
        checks.append(("the load has fallen below 10 % of the peak", out["final_load_over_peak"] < 0.1))
    checks.append(("max |energy error| <= 1 %", out["max_energy_error"] <= 0.01))
    out["checks"] = {name: bool(ok) for name, ok in checks}
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)
    summary = {k: v for k, v in out.items() if k not in ("curve", "checks", "run_warning")}  # the warning: on stderr
    print(" ".join("%s=%s" % (k, ("%.4g" % v) if isinstance(v, float) else v) for k, v in summary.items()))
    failed = [name for name, ok in checks if not ok]
    for name in failed:
        sys.stderr.write("%s: check failed: %s\n" % (SCRIPT, name))
    if a.check and failed:
        sys.exit(1)


if __name__ == "__main__":
    main(sys.argv[1:])

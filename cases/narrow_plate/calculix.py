#!/usr/bin/env python3
"""Explicit finite-element solution of the narrow plate with CalculiX (Debian's calculix-ccx),
independent of the lattice: the same half plate, material and Eq. 23 ramp as case.toml.

    python3 cases/narrow_plate/calculix.py OUT_DIR [--size H] [--element CPS4|CPS8R]
        [--case CASE.toml] [--ccx PATH] [--threads N] [--alpha A] [--reuse]

Writes OUT_DIR/narrow_plate_fe.inp (the deck), runs ccx on it, and writes
OUT_DIR/narrow_plate_fe.csv with sigma_y along the plate at the case's end time: the element
column next to the symmetry plane (element centroids, x = H/2) and the width average of every
element row; OUT_DIR/narrow_plate_fe_field.csv holds every element's centroid sigma_y. Prints
the model size, ccx's time increment, the wall time and the L2 relative errors against 1D bar
theory. --reuse reads the output of an earlier run in OUT_DIR instead of running ccx again.

The model: a structured mesh of square plane-stress elements of size H (default 0.5 mm, the
disk radius: two elements per lattice spacing 2r). The case's orthotropic material in the
lattice frame (x = lattice axis = across the plate): D1111 = c11, D2222 = c22 (along the
plate), D1122 = c12, D1212 = c66, and D1133 = D2233 = 0, so that ccx's expanded 3D elements
give exactly the plane-stress stiffness c_ij whatever their out-of-plane strain (D3333 = c22
and D1313 = D2323 = c66 only keep the 3D material positive definite); the out-of-plane
thickness (H) does not change the stresses. Symmetry plane x = 0: u_x = 0. End y = 0:
pressure q0 times the Eq. 23 ramp (*AMPLITUDE). *DYNAMIC, EXPLICIT (lumped masses) with
ALPHA = 0 (no numerical damping) and the time increment of ccx's own stability estimate.
Stresses: the mean of each element's integration points at the step's end.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import time as clock

import numpy as np

sys.dont_write_bytecode = True  # no __pycache__ in the source tree (the ctest imports these)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import plate as pl  # noqa: E402

SCRIPT = "calculix.py"
JOB = "narrow_plate_fe"


def write_deck(path, plate, size, element, alpha):
    """Writes the CalculiX input deck; returns (nx, ny) elements across and along."""
    nx = int(round(plate.half_width / size))
    ny = int(round(plate.length / size))
    if abs(nx * size - plate.half_width) > 1e-9 or abs(ny * size - plate.length) > 1e-9:
        pl.fail(SCRIPT, "--size %g m does not divide the plate (%g m x %g m) into whole elements"
                % (size, plate.half_width, plate.length))
    quadratic = element == "CPS8R"
    # Grid of nodes: column i (x = i s), row j (y = -j s), s = size or size/2 (midside nodes).
    step = 2 if quadratic else 1
    cols, rows = nx * step + 1, ny * step + 1
    ds = size / step

    def node(i, j):
        return j * cols + i + 1

    out = ["*HEADING", "hexdem narrow plate (paper Section 5.1, example 2): half model, %s, "
           "element size %g m" % (element, size)]
    out.append("*NODE, NSET=NALL")
    for j in range(rows):
        for i in range(cols):
            if quadratic and i % 2 == 1 and j % 2 == 1:
                continue  # element centres: no node in an 8-node quad
            out.append("%d, %.12e, %.12e" % (node(i, j), i * ds, -j * ds))
    out.append("*ELEMENT, TYPE=%s, ELSET=PLATE" % element)
    for j in range(ny):
        for i in range(nx):
            a, b = i * step, j * step  # upper-left corner (x = a ds, y = -b ds)
            # Counter-clockwise from the lower-left corner; face 3 (nodes 3-4) is the upper edge.
            corners = [node(a, b + step), node(a + step, b + step), node(a + step, b), node(a, b)]
            if quadratic:
                mids = [node(a + 1, b + 2), node(a + 2, b + 1), node(a + 1, b), node(a, b + 1)]
                first = ", ".join(str(n) for n in corners + mids[:3])
                out.append("%d, %s," % (j * nx + i + 1, first))
                out.append("%d" % mids[3])
            else:
                out.append("%d, %s" % (j * nx + i + 1, ", ".join(str(n) for n in corners)))
    out.append("*NSET, NSET=SYMMETRY")
    out.extend("%d," % node(0, j) for j in range(rows))
    out.append("*ELSET, ELSET=LOADED")
    out.extend("%d," % (i + 1) for i in range(nx))
    # Lattice frame, plane stress: D1133 = D2233 = 0 decouples the out-of-plane strain.
    c11, c12, c22, c66 = plate.c11, plate.c12, plate.c22, plate.c66
    out += ["*MATERIAL, NAME=PLATE_MATERIAL",
            "*ELASTIC, TYPE=ORTHO",
            "%.10e, %.10e, %.10e, 0., 0., %.10e, %.10e, %.10e," % (c11, c12, c22, c22, c66, c66),
            "%.10e, 0." % c66,
            "*DENSITY",
            "%.10e" % plate.density,
            "*SOLID SECTION, ELSET=PLATE, MATERIAL=PLATE_MATERIAL",
            "%.12e" % size,
            "*AMPLITUDE, NAME=EQ23",  # Eq. 23: q0 t / t1, then q0 until t2, then 0
            "0., 0., %.12e, 1., %.12e, 1., %.12e, 0." % (plate.t1, plate.t2, plate.t2 * (1 + 1e-9)),
            "*BOUNDARY",
            "SYMMETRY, 1, 1, 0.",
            "*STEP, INC=10000000",
            "*DYNAMIC, EXPLICIT, ALPHA=%g" % alpha,
            "%.12e, %.12e" % (plate.t_end / 1000.0, plate.t_end),
            "*DLOAD, AMPLITUDE=EQ23",
            "LOADED, P3, %.10e" % plate.q0,
            # Printed at the step's last increment only (ccx writes the step end in any case).
            "*EL PRINT, ELSET=PLATE, FREQUENCY=100000000",
            "S",
            "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return nx, ny


def fortran_float(text):
    """A number of ccx's output; Fortran drops the E of three-digit exponents (1.5-100)."""
    try:
        return float(text)
    except ValueError:
        return float(re.sub(r"(?<=[0-9.])([+-][0-9]{3})$", r"E\1", text))


def read_stresses(path):
    """The last block of integration-point stresses of the .dat: (time, {element: [rows]})."""
    try:
        with open(path) as f:
            text = f.read()
    except OSError as e:
        pl.fail(SCRIPT, "%s: cannot open: %s" % (path, e.strerror))
    heads = list(re.finditer(r"stresses \(elem, integ\.pnt\.,sxx,syy,szz,sxy,sxz,syz\) for set "
                             r"\S+ and time\s+(\S+)", text))
    if not heads:
        pl.fail(SCRIPT, "%s: no stress output" % path)
    last = heads[-1]
    body = text[last.end():]
    values = {}
    for line in body.splitlines():
        parts = line.split()
        if not parts:
            if values:
                break
            continue
        if len(parts) != 8:
            break
        values.setdefault(int(parts[0]), []).append([fortran_float(v) for v in parts[2:]])
    return float(last.group(1)), values


def fe_profiles(stresses, nx, ny, size):
    """sigma_y profiles from the element-centroid stresses (mean over the integration points):
    the column next to the symmetry plane and the width average of each row."""
    syy = np.zeros((ny, nx))
    for j in range(ny):
        for i in range(nx):
            rows = stresses.get(j * nx + i + 1)
            if rows is None:
                pl.fail(SCRIPT, "no stresses for element %d in the .dat" % (j * nx + i + 1))
            syy[j, i] = np.mean([r[1] for r in rows])
    depth = (np.arange(ny) + 0.5) * size
    return (pl.Profile(depth, syy[:, 0], "FE, axis column"),
            pl.Profile(depth, syy.mean(axis=1), "FE, width average"), syy)


def write_field_csv(path, syy, size):
    """The element-centroid sigma_y field: x, y [m], sigma_y [Pa], one element a row."""
    ny, nx = syy.shape
    with open(path, "w") as f:
        f.write("x_m,y_m,sigma_y_Pa\n")
        for j in range(ny):
            for i in range(nx):
                f.write("%.9e,%.9e,%.9e\n" % ((i + 0.5) * size, -(j + 0.5) * size, syy[j, i]))


def run(out_dir, plate, size=0.5e-3, element="CPS4", ccx="ccx", threads=1, alpha=0.0,
        quiet=False, reuse=False):
    """Writes the deck, runs ccx (unless `reuse`), returns a dict of results with the two
    profiles."""
    os.makedirs(out_dir, exist_ok=True)
    deck = os.path.join(out_dir, JOB + ".inp")
    log = os.path.join(out_dir, JOB + ".log")
    if reuse:
        nx, ny = int(round(plate.half_width / size)), int(round(plate.length / size))
        try:
            with open(log) as f:
                stdout = f.read()
        except OSError as e:
            pl.fail(SCRIPT, "%s: cannot open (no earlier run to reuse): %s" % (log, e.strerror))
        wall = float("nan")
    else:
        exe = shutil.which(ccx)
        if exe is None:
            pl.fail(SCRIPT, "CalculiX '%s' not found (Debian package calculix-ccx)" % ccx)
        nx, ny = write_deck(deck, plate, size, element, alpha)
        env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_STIFFNESS=str(threads),
                   CCX_NPROC_RESULTS=str(threads))
        start = clock.monotonic()
        proc = subprocess.run([exe, "-i", JOB], cwd=out_dir, env=env, capture_output=True,
                              text=True)
        wall = clock.monotonic() - start
        stdout = proc.stdout
        with open(log, "w") as f:
            f.write(proc.stdout + proc.stderr)
        if proc.returncode != 0 or "Job finished" not in proc.stdout:
            tail = [ln for ln in (proc.stdout + proc.stderr).splitlines() if ln.strip()][-3:]
            pl.fail(SCRIPT, "ccx failed on %s (exit %d): %s" % (deck, proc.returncode,
                                                                 " | ".join(tail)))
    m = re.search(r"SELECTED time increment:\s*(\S+)", stdout)
    dt = float(m.group(1)) if m else float("nan")
    t, stresses = read_stresses(os.path.join(out_dir, JOB + ".dat"))
    if abs(t - plate.t_end) > 1e-6 * plate.t_end:
        pl.fail(SCRIPT, "the .dat's last stresses are at t = %g s, not the end time %g s"
                % (t, plate.t_end))
    axis, mean, field = fe_profiles(stresses, nx, ny, size)
    pl.write_profiles_csv(os.path.join(out_dir, JOB + ".csv"), [axis, mean])
    write_field_csv(os.path.join(out_dir, JOB + "_field.csv"), field, size)
    result = dict(element=element, size=size, elements=nx * ny, dt=dt, wall=wall, time=t,
                  axis=axis, mean=mean, l2_axis_bar=axis.l2_against_bar(plate, t),
                  l2_mean_bar=mean.l2_against_bar(plate, t))
    if not quiet:
        timing = "output of an earlier run" if reuse else "wall %.1f s (%d thread%s)" % (
            wall, threads, "" if threads == 1 else "s")
        print("CalculiX %s, element size %.4g mm: %d elements, time increment %.4g ns, %s"
              % (element, size * 1e3, nx * ny, dt * 1e9, timing))
        print("  sigma_y at t = %.4g us, L2 relative error against bar theory: axis column %.4f, "
              "width average %.4f" % (t * 1e6, result["l2_axis_bar"], result["l2_mean_bar"]))
        print("  profiles: %s" % os.path.join(out_dir, JOB + ".csv"))
    return result


def main(argv):
    parser = argparse.ArgumentParser(description="CalculiX explicit solution of the narrow plate.")
    parser.add_argument("out_dir", help="folder for the deck, ccx's output and the profiles")
    parser.add_argument("--size", type=float, default=0.5e-3, help="element size [m] (0.5e-3)")
    parser.add_argument("--element", choices=("CPS4", "CPS8R"), default="CPS4")
    parser.add_argument("--case", default=pl.CASE_FILE, help="case file (this folder's case.toml)")
    parser.add_argument("--ccx", default="ccx", help="CalculiX executable (ccx)")
    parser.add_argument("--threads", type=int, default=1, help="OpenMP threads of ccx (1)")
    parser.add_argument("--alpha", type=float, default=0.0,
                        help="ccx's *DYNAMIC ALPHA, in [-1/3, 0] (0: no numerical damping)")
    parser.add_argument("--reuse", action="store_true",
                        help="read the output of an earlier run in OUT_DIR (same --size)")
    args = parser.parse_args(argv)
    if args.size <= 0:
        pl.fail(SCRIPT, "--size must be > 0 (got %g)" % args.size)
    if not -1.0 / 3.0 <= args.alpha <= 0.0:
        pl.fail(SCRIPT, "--alpha must lie in [-1/3, 0] (got %g)" % args.alpha)
    plate = pl.load_plate(SCRIPT, args.case)
    run(args.out_dir, plate, args.size, args.element, args.ccx, args.threads, args.alpha,
        reuse=args.reuse)


if __name__ == "__main__":
    main(sys.argv[1:])

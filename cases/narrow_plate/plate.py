"""Shared parts of the narrow-plate scripts (calculix.py, figures.py, check.py): the plate's
geometry, material and load as case.toml and outline.toml give them, 1D bar theory for the
Eq. 23 ramp, sigma_y profiles of a hexdem result frame, and L2 relative errors.

Units are SI (m, s, Pa, kg) everywhere in these scripts. Stresses are tension positive, so the
compressive ramp gives sigma_y < 0. The plate is the half x in [0, W] (symmetry plane x = 0),
y in [-L, 0], loaded on its end y = 0; "depth" is d = -y, the distance from the loaded end.
"""

import math
import os
import sys
import tomllib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CASE_FILE = os.path.join(HERE, "case.toml")

UNIT_SCALE = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "um": 1e-6}


def fail(script, message):
    """Prints a one-line error and exits with code 1."""
    sys.stderr.write("%s: %s\n" % (script, message))
    sys.exit(1)


class Plate:
    """The narrow plate of case.toml: geometry [m], material B [Pa, kg/m^3], ramp load."""

    def __init__(self, half_width, length, radius, thickness, density, c11, c12, c22, c66,
                 q0, t1, t2, t_end):
        self.half_width = half_width  # W [m]: the half model spans x in [0, W]
        self.length = length          # L [m]: y in [-L, 0]
        self.radius = radius          # disk radius r [m]
        self.thickness = thickness    # [m]
        self.density = density        # rho [kg/m^3]
        self.c11, self.c12, self.c22, self.c66 = c11, c12, c22, c66  # [Pa], x = lattice axis
        self.q0, self.t1, self.t2 = q0, t1, t2  # Eq. 23: q0 [Pa], t1, t2 [s]
        self.t_end = t_end            # [s]

    @property
    def bar_modulus(self):
        """Young's modulus along y in plane stress with sigma_x = 0: c22 - c12^2/c11 [Pa]."""
        return self.c22 - self.c12 ** 2 / self.c11

    @property
    def bar_speed(self):
        """1D bar wave speed along the plate, sqrt((c22 - c12^2/c11)/rho) [m/s]."""
        return math.sqrt(self.bar_modulus / self.density)

    def ramp(self, t):
        """Eq. 23's factor p(t)/q0: t/t1 up to t1, 1 up to t2, 0 after (arrays allowed)."""
        t = np.asarray(t, dtype=float)
        return np.where(t <= 0, 0.0, np.where(t <= self.t1, t / self.t1,
                                              np.where(t <= self.t2, 1.0, 0.0)))

    def bar_sigma_y(self, depth, t):
        """sigma_y [Pa] of 1D bar theory at distance `depth` [m] from the loaded end, time t:
        the end stress travels undistorted at the bar speed, sigma_y = -q0 f(t - d/c). Valid
        while the front has not reached the far end (c t <= L); later times are refused."""
        if self.bar_speed * t > self.length:
            raise ValueError("bar theory here has no reflection: t = %g s is after the front "
                             "reached the far end" % t)
        return -self.q0 * self.ramp(t - np.asarray(depth, dtype=float) / self.bar_speed)


def _get(script, path, table, key, where):
    if key not in table:
        fail(script, "%s: %s: missing key '%s'" % (path, where, key))
    return table[key]


def _read_toml(script, path):
    """The parsed TOML file, or a one-line error naming it."""
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except OSError as e:
        fail(script, "%s: cannot open: %s" % (path, e.strerror))
    except tomllib.TOMLDecodeError as e:
        fail(script, "%s: TOML parse error: %s" % (path, e))


def load_plate(script, case_path=CASE_FILE, radius=None):
    """Reads the plate from the case file and its outline. `radius` [m] overrides the
    lattice radius (as the case file's [mesh] radius would). One-line errors name the file and
    key."""
    case = _read_toml(script, case_path)
    mesh = _get(script, case_path, case, "mesh", "top level")
    outline_path = os.path.join(os.path.dirname(case_path),
                                _get(script, case_path, mesh, "outline", "mesh"))
    outline = _read_toml(script, outline_path)
    units = outline.get("units", "m")
    if units not in UNIT_SCALE:
        fail(script, "%s: units: unknown unit '%s'" % (outline_path, units))
    scale = UNIT_SCALE[units]
    bodies = outline.get("body", [])
    if len(bodies) != 1 or len(bodies[0].get("shape", [])) != 1 \
            or bodies[0]["shape"][0].get("type") != "rectangle":
        fail(script, "%s: body: expected one body made of one rectangle (the plate)" % outline_path)
    shape = bodies[0]["shape"][0]
    (x0, y0), (x1, y1) = shape["min"], shape["max"]
    if x0 != 0 or y1 != 0:
        fail(script, "%s: body[0].shape[0]: expected min = [0, -L] and max = [W, 0] (got min = %s, "
             "max = %s)" % (outline_path, shape["min"], shape["max"]))
    if radius is None:
        radius = mesh.get("radius", outline.get("lattice", {}).get("radius", 0) * scale)
    materials = _get(script, case_path, case, "material", "top level")
    mat = materials[0]
    for key in ("density", "c11", "c12", "c22", "c66"):
        _get(script, case_path, mat, key, "material[0]")
    loads = [ld for ld in case.get("load", []) if ld.get("type") == "pressure"]
    if len(loads) != 1:
        fail(script, "%s: load: expected one pressure load (got %d)" % (case_path, len(loads)))
    function = _get(script, case_path, loads[0], "function", "load[0]")
    if function.get("type") != "ramp-hold":
        fail(script, "%s: load[0].function.type: expected \"ramp-hold\" (got \"%s\")"
             % (case_path, function.get("type")))
    time = _get(script, case_path, case, "time", "top level")
    return Plate(half_width=x1 * scale, length=-y0 * scale, radius=radius,
                 thickness=case.get("case", {}).get("thickness", 1.0), density=mat["density"],
                 c11=mat["c11"], c12=mat["c12"], c22=mat["c22"], c66=mat["c66"],
                 q0=loads[0]["p0"], t1=function["t1"], t2=function["t2"],
                 t_end=_get(script, case_path, time, "end", "time"))


def l2_error(sim, ref):
    """Relative L2 error sqrt(sum (sim - ref)^2 / sum ref^2) over the sample points."""
    sim, ref = np.asarray(sim, dtype=float), np.asarray(ref, dtype=float)
    return float(np.sqrt(np.sum((sim - ref) ** 2) / np.sum(ref ** 2)))


class Profile:
    """sigma_y along the plate: depth d = -y [m] (increasing) and sigma_y [Pa]."""

    def __init__(self, depth, sigma_y, label):
        order = np.argsort(depth)
        self.depth = np.asarray(depth, dtype=float)[order]
        self.sigma_y = np.asarray(sigma_y, dtype=float)[order]
        self.label = label

    def at(self, depth):
        """Linear interpolation at `depth` (inside the sampled range)."""
        return np.interp(depth, self.depth, self.sigma_y)

    def l2_against(self, other):
        """L2 relative error of this profile against `other`, at this profile's points (linear
        interpolation of `other`; its end values beyond its sampled range)."""
        return l2_error(self.sigma_y, other.at(self.depth))

    def l2_against_bar(self, plate, t):
        return l2_error(self.sigma_y, plate.bar_sigma_y(self.depth, t))


def read_frame(script, path):
    """A hexdem result frame (.vtu) as (time [s], initial x, initial y, stress_yy, cell_area)."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    if not os.path.isfile(path):
        fail(script, "%s: no such file" % path)
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    if data is None or data.GetNumberOfPoints() == 0:
        fail(script, "%s: no disks (not a hexdem frame?)" % path)
    arrays = {}
    for name in ("displacement", "stress", "cell_area"):
        a = data.GetPointData().GetArray(name)
        if a is None:
            fail(script, "%s: no '%s' point array (not a hexdem frame?)" % (path, name))
        arrays[name] = vtk_to_numpy(a)
    time = data.GetFieldData().GetArray("time")
    if time is None:
        fail(script, "%s: no 'time' field array (not a hexdem frame?)" % path)
    points = vtk_to_numpy(data.GetPoints().GetData())
    x0 = points[:, 0] - arrays["displacement"][:, 0]
    y0 = points[:, 1] - arrays["displacement"][:, 1]
    return time.GetValue(0), x0, y0, arrays["stress"][:, 4], arrays["cell_area"]


def frame_at(script, series, t):
    """The .vtu of the frame of a .pvd series nearest to time t [s], and its time."""
    import xml.etree.ElementTree as ET
    try:
        root = ET.parse(series).getroot()
    except (OSError, ET.ParseError) as e:
        fail(script, "%s: cannot read the series: %s" % (series, e))
    sets = [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]
    if not sets:
        fail(script, "%s: no frames" % series)
    time, name = min(sets, key=lambda s: abs(s[0] - t))
    return os.path.join(os.path.dirname(series), name), time


def lattice_profiles(script, vtu, radius):
    """The lattice's sigma_y along the plate from a frame: the disks on the axis (x = 0), and
    the width average of every lattice row (cell-area weighted, so that the semi-disks on the
    edges count for their share of the width). Returns (time, axis Profile, mean Profile)."""
    time, x0, y0, syy, area = read_frame(script, vtu)
    on_axis = np.abs(x0) < 1e-3 * radius
    if not np.any(on_axis):
        fail(script, "%s: no disks on the axis x = 0" % vtu)
    axis = Profile(-y0[on_axis], syy[on_axis], "lattice, axis disks")
    row = np.round(-y0 / (math.sqrt(3.0) * radius)).astype(int)  # rows are sqrt(3) r apart
    rows = np.unique(row)
    weight = np.bincount(row - rows[0], weights=area)
    mean = np.bincount(row - rows[0], weights=area * syy) / np.where(weight > 0, weight, 1.0)
    depth = np.bincount(row - rows[0], weights=area * -y0) / np.where(weight > 0, weight, 1.0)
    used = weight > 0
    return time, axis, Profile(depth[used], mean[used], "lattice, width average")


def write_profiles_csv(path, profiles):
    """One CSV of several profiles: columns label, depth [m], sigma_y [Pa]."""
    with open(path, "w") as f:
        f.write("profile,depth_m,sigma_y_Pa\n")
        for p in profiles:
            for d, s in zip(p.depth, p.sigma_y):
                f.write("%s,%.9e,%.9e\n" % (p.label, d, s))


def read_profiles_csv(script, path):
    """The profiles written by write_profiles_csv, by label."""
    out = {}
    try:
        with open(path) as f:
            header = f.readline().strip()
            if header != "profile,depth_m,sigma_y_Pa":
                fail(script, "%s: not a profile file (header '%s')" % (path, header))
            for line in f:
                label, d, s = line.rstrip("\n").rsplit(",", 2)
                out.setdefault(label, ([], []))
                out[label][0].append(float(d))
                out[label][1].append(float(s))
    except OSError as e:
        fail(script, "%s: cannot open: %s" % (path, e.strerror))
    return {k: Profile(v[0], v[1], k) for k, v in out.items()}

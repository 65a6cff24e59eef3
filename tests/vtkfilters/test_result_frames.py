"""Result frames name their bodies and carry the lattice file's boundary sets, and ParaView
can use them: a two-body case (data/two_bodies) is meshed (`hexdem mesh`) and run (`hexdem
run`); in pvpython the frames' `body_names`, `boundary_sets` and set arrays are compared with
the lattice file, a set is selected with Threshold, the fragment counter leaves the
projectile out when asked to count the target only, and the max shear filter does not warn
about the missing p_max on every frame.

    pvpython test_result_frames.py HEXDEM DATA_DIR WORK_DIR [PLUGIN.so]
"""

import os
import shutil
import subprocess
import sys

from paraview import servermanager
from paraview import simple as pv
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.util.vtkConstants import VTK_STRING


def check(condition, message):
    if not condition:
        print("FAIL: " + message)
        sys.exit(1)


def strings(data, name):
    array = data.GetFieldData().GetAbstractArray(name)
    check(array is not None, "no '%s' field data" % name)
    return [array.GetValue(k) for k in range(array.GetNumberOfValues())]


def field(data, name):
    return data.GetFieldData().GetArray(name).GetValue(0)


def main():
    hexdem, data_dir, work = sys.argv[1:4]
    if len(sys.argv) > 4:
        pv.LoadPlugin(sys.argv[4], remote=False)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    lattice_path = os.path.join(work, "lattice.vtu")
    for args in (["mesh", os.path.join(data_dir, "outline.toml"), "-o", lattice_path, "-q"],
                 ["run", os.path.join(data_dir, "case.toml"), "-o", os.path.join(work, "out"), "-q"]):
        run = subprocess.run([hexdem] + args, capture_output=True, text=True)
        check(run.returncode == 0, "hexdem %s: exit %d: %s" % (args[0], run.returncode, run.stderr))

    lattice = servermanager.Fetch(pv.XMLUnstructuredGridReader(FileName=[lattice_path]))
    series = pv.PVDReader(FileName=os.path.join(work, "out", "two_bodies.pvd"))
    times = list(series.TimestepValues)
    check(len(times) == 3, "%d frames" % len(times))
    sets = ["base", "impact", "sym", "skin"]
    for t in times:
        series.UpdatePipeline(t)
        frame = servermanager.Fetch(series)
        check(frame.GetNumberOfPoints() == lattice.GetNumberOfPoints(), "disk counts differ")
        check(strings(frame, "body_names") == strings(lattice, "body_names") == ["target", "projectile"],
              "body_names %s" % strings(frame, "body_names"))
        check(strings(frame, "boundary_sets") == sets, "boundary_sets %s" % strings(frame, "boundary_sets"))
        for name in sets:
            got = frame.GetPointData().GetArray(name)
            check(got is not None and got.GetDataTypeAsString() == "unsigned char",
                  "t=%g: no UInt8 point array '%s'" % (t, name))
            expected = vtk_to_numpy(lattice.GetPointData().GetArray(name))
            check((vtk_to_numpy(got) == expected).all() and expected.sum() > 0,
                  "t=%g: set '%s' differs from the lattice file" % (t, name))

    # A set selected in ParaView: Threshold on its array keeps its members.
    skin = pv.Threshold(Input=series, Scalars=["POINTS", "skin"], LowerThreshold=0.5,
                        UpperThreshold=1.5, AllScalars=1)
    selected = servermanager.Fetch(skin)
    members = int(vtk_to_numpy(lattice.GetPointData().GetArray("skin")).sum())
    body = vtk_to_numpy(selected.GetPointData().GetArray("body"))
    check(selected.GetNumberOfPoints() >= members and (body == 1).all(),
          "Threshold on 'skin': %d points, bodies %s" % (selected.GetNumberOfPoints(), set(body)))

    # Fragments: two intact bodies are two fragments; the target alone is one.
    fragments = pv.HexDEMFragmentCounter(Input=series)
    out = servermanager.Fetch(fragments)
    check(field(out, "fragment_count") == 2, "fragment_count %g" % field(out, "fragment_count"))
    table = servermanager.Fetch(fragments, idx=1)
    names = sorted(table.GetValueByName(r, "body_name").ToString() for r in range(table.GetNumberOfRows()))
    check(names == ["projectile", "target"], "body_name column %s" % names)
    fragments.BodyName = "target"
    out = servermanager.Fetch(fragments)
    check(field(out, "fragment_count") == 1, "target only: fragment_count %g" % field(out, "fragment_count"))
    ids = vtk_to_numpy(out.GetPointData().GetArray("fragment_id"))
    bodies = vtk_to_numpy(out.GetPointData().GetArray("body"))
    check((ids[bodies == 1] == -1).all() and (ids[bodies == 0] == 0).all(), "fragment_id by body")
    # Max shear on an impact series (no pressure load, no p_max): silent on every frame by
    # default; one warning over the series when the ratio is asked for.
    shear = pv.HexDEMMaxShearStress(Input=series)
    warnings = []

    @calldata_type(VTK_STRING)
    def on_warning(obj, event, message):
        warnings.append(message)

    shear.GetClientSideObject().AddObserver("WarningEvent", on_warning)
    for t in times:
        shear.UpdatePipeline(t)
        check(servermanager.Fetch(shear).GetPointData().GetArray("max_shear_ratio") is None, "ratio without p_max")
    check(warnings == [], "warnings without a ratio asked for: %s" % warnings)
    shear.RatioMode = "On"
    for t in times + times:
        shear.UpdatePipeline(t)
    check(len(warnings) == 1 and "No peak pressure" in warnings[0],
          "RatioMode On over %d frames: %d warnings %s" % (2 * len(times), len(warnings), warnings))

    # `hexdem post fragments`: the table's CSV names each fragment's body.
    csv = os.path.join(work, "fragments")
    run = subprocess.run([hexdem, "post", "fragments", os.path.join(work, "out", "two_bodies.pvd"),
                          "-o", csv, "--csv-only", "-q"], capture_output=True, text=True)
    check(run.returncode == 0, "hexdem post fragments: %s" % run.stderr)
    with open(csv + ".csv") as f:
        rows = [line.rstrip("\n").split(",") for line in f]
    check(rows[0][-2:] == ["body", "body_name"], "CSV header %s" % rows[0])
    check(sorted(r[-1] for r in rows[1:]) == ["projectile", "target"], "CSV body_name %s" % rows[1:])

    print("OK: %d disks, sets %s, bodies %s" % (lattice.GetNumberOfPoints(), sets,
                                                  strings(lattice, "body_names")))


if __name__ == "__main__":
    main()

"""The HexDEMFilters ParaView plugin in pvpython/pvbatch: the three filters are in the
"hexdem" menu category, run on a frame (.vtu) and on a time series (.pvd), and report bad
input without crashing. Results are fetched with servermanager.Fetch and checked against
values computed independently (frame_checks.py).

    pvpython test_plugin.py FRAMES_DIR [PLUGIN.so]

Without PLUGIN.so the plugin must already be loaded (PV_PLUGIN_PATH).
"""

import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from paraview import servermanager  # noqa: E402
from paraview import simple as pv  # noqa: E402
from vtkmodules.util.misc import calldata_type  # noqa: E402
from vtkmodules.util.vtkConstants import VTK_STRING  # noqa: E402

from frame_checks import (cell_array, check, close, crack_counts, field,  # noqa: E402
                          fragment_sizes, max_shear, point_array)

FILTERS = ("HexDEMMaxShearStress", "HexDEMCrackMap", "HexDEMFragmentCounter")


def load(frames_dir, plugin):
    if plugin:
        pv.LoadPlugin(plugin, remote=False)
    for name in FILTERS:
        check(hasattr(pv, name), "paraview.simple has no %s: the plugin is not loaded" % name)


def test_menu_category():
    pxm = servermanager.vtkSMProxyManager.GetProxyManager().GetActiveSessionProxyManager()
    for name in FILTERS:
        proxy = pxm.GetPrototypeProxy("filters", name)
        check(proxy is not None, "no proxy filters/%s" % name)
        menu = proxy.GetHints().FindNestedElementByName("ShowInMenu")
        check(menu is not None and menu.GetAttribute("category") == "hexdem",
              "%s is not in the hexdem menu category" % name)


def test_frame(frames_dir):
    reader = pv.XMLUnstructuredGridReader(FileName=[os.path.join(frames_dir, "fractured.vtu")])
    frame = servermanager.Fetch(reader)
    n = frame.GetNumberOfPoints()
    check(n == 9600, "fractured.vtu has %d disks" % n)

    # Maximum shear stress and its ratio to the frame's p_max (1e7 Pa).
    shear = pv.HexDEMMaxShearStress(Input=reader)
    out = servermanager.Fetch(shear)
    tau = point_array(out, "max_shear")
    expected = max_shear(frame)
    check(abs(tau - expected).max() <= 1e-9 * expected.max(), "max_shear differs")
    ratio = point_array(out, "max_shear_ratio")
    check(abs(ratio - expected / 1e7).max() <= 1e-15 * (1 + expected.max()), "max_shear_ratio differs")
    shear.PMax = 2e7
    shear.ComputeThreeDimensional = 1
    out = servermanager.Fetch(shear)
    check(abs(point_array(out, "max_shear_ratio") - expected / 2e7).max() < 1e-12, "PMax ignored")
    tau3 = point_array(out, "max_shear_3d")
    check((tau3 >= tau - 1e-9 * expected.max()).all(), "max_shear_3d < max_shear")
    shear.StressSource = "Bond forces"
    out = servermanager.Fetch(shear)
    check(out.GetPointData().GetArray("recovered_stress") is not None, "no recovered_stress")

    # Crack map: counts and nominal lengths per mode, merged or not.
    cracks = pv.HexDEMCrackMap(Input=reader)
    out = servermanager.Fetch(cracks)
    counts, lengths = crack_counts(frame)
    names = {2: "tension", 3: "shear", 4: "compression"}
    for mode, name in names.items():
        check(field(out, "crack_count_" + name) == counts[mode],
              "crack_count_%s %g != %d" % (name, field(out, "crack_count_" + name), counts[mode]))
        check(close(field(out, "crack_length_" + name), lengths[mode], 1e-12),
              "crack_length_%s differs" % name)
    total = sum(counts.values())
    check(field(out, "crack_count") == total, "crack_count differs")
    check(out.GetNumberOfCells() < total, "segments were not merged into polylines")
    cracks.MergeSegments = 0
    out = servermanager.Fetch(cracks)
    check(out.GetNumberOfCells() == total, "unmerged: %d cells for %d bonds" % (out.GetNumberOfCells(), total))
    cracks.UseMaxBreakTime = 1
    cracks.MaxBreakTime = 5e-5
    out = servermanager.Fetch(cracks)
    state, times = cell_array(frame, "state"), cell_array(frame, "break_time")
    early = int((((state >= 2) & (state <= 4)) & (times <= 5e-5)).sum())
    check(field(out, "crack_count") == early, "MaxBreakTime: %g != %d" % (field(out, "crack_count"), early))

    # Fragments: the count and sizes of an independent union-find; the table.
    fragments = pv.HexDEMFragmentCounter(Input=reader)
    out = servermanager.Fetch(fragments)
    table = servermanager.Fetch(fragments, idx=1)
    sizes = fragment_sizes(frame)
    check(field(out, "fragment_count") == len(sizes),
          "fragment_count %g != %d" % (field(out, "fragment_count"), len(sizes)))
    check(table.GetNumberOfRows() == len(sizes), "table rows %d" % table.GetNumberOfRows())
    disks = [table.GetValueByName(r, "disks").ToInt() for r in range(table.GetNumberOfRows())]
    check(disks == sizes, "fragment sizes differ")
    ids = point_array(out, "fragment_id")
    check(int(ids.max()) == len(sizes) - 1 and (ids == 0).sum() == sizes[0], "fragment_id")
    mass = sum(table.GetValueByName(r, "mass").ToDouble() for r in range(table.GetNumberOfRows()))
    check(close(mass, point_array(frame, "mass").sum(), 1e-12), "fragment masses do not add up")
    fragments.MinimumDisks = 10
    out = servermanager.Fetch(fragments)
    large = sum(1 for s in sizes if s >= 10)
    check(field(out, "fragment_count") == large, "MinimumDisks")
    check(servermanager.Fetch(fragments, idx=1).GetNumberOfRows() == large, "MinimumDisks table")
    for proxy in (fragments, cracks, shear, reader):
        pv.Delete(proxy)


def test_series(frames_dir):
    reader = pv.PVDReader(FileName=os.path.join(frames_dir, "series.pvd"))
    times = list(reader.TimestepValues)
    check(len(times) == 3 and times[0] == 0.0 and close(times[2], 2e-5), "times %s" % times)
    shear = pv.HexDEMMaxShearStress(Input=reader)
    cracks = pv.HexDEMCrackMap(Input=reader)
    fragments = pv.HexDEMFragmentCounter(Input=reader)
    expected_fragments = []
    for t in times:
        reader.UpdatePipeline(t)
        frame = servermanager.Fetch(reader)
        check(close(field(frame, "time"), t), "reader time")
        shear.UpdatePipeline(t)
        out = servermanager.Fetch(shear)
        check(close(field(out, "time"), t), "max shear at the wrong time")
        check(abs(point_array(out, "max_shear") - max_shear(frame)).max() < 1e-6, "series max_shear")
        cracks.UpdatePipeline(t)
        out = servermanager.Fetch(cracks)
        counts, _ = crack_counts(frame)
        check(field(out, "crack_count") == sum(counts.values()),
              "t=%g: crack_count %g != %d" % (t, field(out, "crack_count"), sum(counts.values())))
        fragments.UpdatePipeline(t)
        out = servermanager.Fetch(fragments)
        expected_fragments.append(len(fragment_sizes(frame)))
        check(field(out, "fragment_count") == expected_fragments[-1], "t=%g: fragment_count" % t)
        table = servermanager.Fetch(fragments, idx=1)
        check(table.GetNumberOfRows() == expected_fragments[-1], "t=%g: table rows" % t)
    check(expected_fragments == [1, 2, 3], "series fragments %s" % expected_fragments)
    for proxy in (fragments, cracks, shear, reader):
        pv.Delete(proxy)


def test_bad_input(frames_dir):
    """Errors are reported, outputs are empty, and the session goes on."""
    bad = os.path.join(frames_dir, "bad")
    cases = [("no_state.vtu", "HexDEMCrackMap", {}, "'state'"),
             ("no_state.vtu", "HexDEMFragmentCounter", {}, "'state'"),
             ("no_stress.vtu", "HexDEMMaxShearStress", {}, "'normal_force'"),
             ("no_stress.vtu", "HexDEMMaxShearStress", {"StressSource": "Point array stress"},
              "'stress'"),
             ("not_hexdem.vtu", "HexDEMCrackMap", {}, "'state'"),
             ("not_hexdem.vtu", "HexDEMFragmentCounter", {}, "'state'"),
             ("not_hexdem.vtu", "HexDEMMaxShearStress", {}, "'radius'")]
    for file_name, filter_name, properties, expected in cases:
        reader = pv.XMLUnstructuredGridReader(FileName=[os.path.join(bad, file_name)])
        proxy = getattr(pv, filter_name)(Input=reader, **properties)
        errors = []

        @calldata_type(VTK_STRING)
        def on_error(obj, event, message):
            errors.append(message)

        proxy.GetClientSideObject().AddObserver("ErrorEvent", on_error)
        proxy.UpdatePipeline()
        out = servermanager.Fetch(proxy)
        check(out.GetNumberOfPoints() == 0 and out.GetNumberOfCells() == 0,
              "%s on %s: output not empty" % (filter_name, file_name))
        check(any(expected in e for e in errors),
              "%s on %s: no error naming %s (got %s)" % (filter_name, file_name, expected, errors))
        pv.Delete(proxy)
        pv.Delete(reader)


def main(argv):
    frames_dir = argv[0]
    plugin = argv[1] if len(argv) > 1 else None
    load(frames_dir, plugin)
    test_menu_category()
    test_frame(frames_dir)
    test_series(frames_dir)
    test_bad_input(frames_dir)
    print("plugin test passed (%s)" % ("LoadPlugin" if plugin else "PV_PLUGIN_PATH"))


if __name__ == "__main__":
    main(sys.argv[1:])

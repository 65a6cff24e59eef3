"""vtkfilters/scripts/hexdem_view.py: the state file it writes opens the series the way
docs/filters.md describes, and bad input is refused.

    python3 test_view_state.py SOURCE_DIR FRAMES_DIR PLUGIN.so WORK_DIR

Runs hexdem_view.py with pvbatch (under a virtual X server, scripts/pvbatch-xvfb.sh) on the
test series, then loads the state in a second pvbatch (this file with --check) and checks
every default: the disks as Point Gaussian splats of radius `radius` coloured by
max_shear_ratio with a colour range from 0 to the series' largest value (not the round-off of
t = 0) that grows with the time steps, the cracks coloured by the categorical `mode` in the figure scripts' colours,
the fragments categorical by `fragment_id`, hidden, with their table in a spreadsheet.
"""

import os
import subprocess
import sys


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def check_state(state, plugin, scripts):
    """Run by pvbatch: loads the state and checks it."""
    sys.path.insert(0, scripts)
    import figure_common as fc
    from paraview import servermanager
    from paraview import simple as pv
    pv.LoadPlugin(plugin, remote=False)
    pv.LoadState(state)
    names = {name: proxy for (name, _), proxy in pv.GetSources().items()}
    for name, xml in (("Disks (max shear)", "HexDEMMaxShearStress"), ("Cracks", "HexDEMCrackMap"),
                      ("Fragments", "HexDEMFragmentCounter"), ("series.pvd", "PVDReader")):
        check(name in names and names[name].GetXMLName() == xml, "no %s '%s' in %s" % (xml, name, sorted(names)))
    views = pv.GetViews()
    render = [v for v in views if v.GetXMLName() == "RenderView"]
    sheets = [v for v in views if v.GetXMLName() == "SpreadSheetView"]
    check(len(render) == 1 and len(sheets) == 1, "views %s" % [v.GetXMLName() for v in views])
    view = render[0]
    check(abs(view.ViewTime - 2e-5) < 1e-12, "shown time %g, expected the last frame" % view.ViewTime)

    # Disks: true size, coloured by the ratio, range of the shown frame, growing.
    shear = names["Disks (max shear)"]
    disks = pv.GetDisplayProperties(shear, view)
    check(disks.Representation == "Point Gaussian", "disks: %s" % disks.Representation)
    check(disks.ScaleByArray == 1 and list(disks.SetScaleArray)[1] == "radius" and disks.GaussianRadius == 1.0
          and disks.UseScaleFunction == 0, "disks are not scaled by radius")
    check(disks.Visibility == 1, "disks hidden")
    check(list(disks.ColorArrayName) == ["POINTS", "max_shear_ratio"], "disks coloured by %s" % disks.ColorArrayName)
    lut = pv.GetColorTransferFunction("max_shear_ratio")
    check(lut.AutomaticRescaleRangeMode == "Grow and update every timestep",
          "max_shear_ratio range mode %s" % lut.AutomaticRescaleRangeMode)
    high = 0.0
    for t in names["series.pvd"].TimestepValues:  # the largest value over the series
        shear.UpdatePipeline(t)
        high = max(high, servermanager.Fetch(shear).GetPointData().GetArray("max_shear_ratio").GetRange()[1])
    points = list(lut.RGBPoints)
    check(high > 1e-3 and abs(points[-4] - high) <= 1e-12 * high and points[0] == 0.0,
          "max_shear_ratio range [%g, %g], series max %g" % (points[0], points[-4], high))

    # Cracks: categorical mode in the figure colours.
    lines = pv.GetDisplayProperties(names["Cracks"], view)
    check(list(lines.ColorArrayName) == ["CELLS", "mode"], "cracks coloured by %s" % lines.ColorArrayName)
    mode = pv.GetColorTransferFunction("mode")
    check(mode.InterpretValuesAsCategories == 1, "mode is not categorical")
    check(list(mode.Annotations) == ["2", "tension", "3", "shear", "4", "compression"],
          "mode annotations %s" % list(mode.Annotations))
    expected = [c for _, _, colour in fc.CRACK_MODES for c in colour]
    check(max(abs(a - b) for a, b in zip(mode.IndexedColors, expected)) < 1e-9 and
          len(mode.IndexedColors) == 9, "mode colours %s" % list(mode.IndexedColors))
    check(list(mode.IndexedColors[:3]) == [0.85, 0.15, 0.10], "tension is not red")

    # Fragments: categorical ids, points only, hidden; the table in the spreadsheet.
    fragments = names["Fragments"]
    pieces = pv.GetDisplayProperties(fragments, view)
    check(pieces.Representation == "Point Gaussian" and pieces.Visibility == 0,
          "fragments: %s, visible %d" % (pieces.Representation, pieces.Visibility))
    check(list(pieces.ColorArrayName) == ["POINTS", "fragment_id"], "fragments coloured by %s" % pieces.ColorArrayName)
    ids = pv.GetColorTransferFunction("fragment_id")
    check(ids.InterpretValuesAsCategories == 1 and len(ids.Annotations) == 24 and
          len(ids.IndexedColors) == 36, "fragment_id is not categorical with 12 colours")
    check(list(ids.IndexedColors[:3]) != list(ids.IndexedColors[3:6]), "fragments 0 and 1 share a colour")
    table = pv.GetDisplayProperties(pv.OutputPort(fragments, 1), sheets[0])
    check(table.Visibility == 1, "the fragment table is not shown")
    print("OK: state checked")
    check_plugin_defaults(pv, names["series.pvd"], view.ViewTime)


def check_plugin_defaults(pv, reader, time):
    """The plugin's own defaults (XML hints, active scalars), without the view script: what
    a GUI user gets from Filters > hexdem."""
    view = pv.CreateView("RenderView")
    view.ViewTime = time
    shown = {}
    for name in ("HexDEMMaxShearStress", "HexDEMCrackMap", "HexDEMFragmentCounter"):
        source = getattr(pv, name)(Input=reader)
        display = pv.Show(source, view)
        shown[name] = (display.GetPropertyValue("Representation"), list(display.ColorArrayName))
    check(shown["HexDEMMaxShearStress"] == ("Point Gaussian", ["POINTS", "max_shear_ratio"]),
          "max shear shown as %s" % (shown["HexDEMMaxShearStress"],))
    check(shown["HexDEMFragmentCounter"] == ("Point Gaussian", ["POINTS", "fragment_id"]),
          "fragments shown as %s" % (shown["HexDEMFragmentCounter"],))
    check(shown["HexDEMCrackMap"] == ("Surface", ["CELLS", "mode"]), "cracks shown as %s" % (shown["HexDEMCrackMap"],))
    from paraview import servermanager
    pxm = servermanager.vtkSMProxyManager.GetProxyManager().GetActiveSessionProxyManager()
    hints = pxm.GetPrototypeProxy("filters", "HexDEMFragmentCounter").GetHints()
    table_view = [hints.GetNestedElement(k) for k in range(hints.GetNumberOfNestedElements())
                  if hints.GetNestedElement(k).GetName() == "View"]
    check(len(table_view) == 1 and table_view[0].GetAttribute("type") == "SpreadSheetView" and
          table_view[0].GetAttribute("port") == "1", "no SpreadSheetView hint for the fragment table")
    print("OK: plugin defaults")


def run(command, **kwargs):
    return subprocess.run(command, capture_output=True, text=True, timeout=300, **kwargs)


def main():
    if sys.argv[1] == "--check":
        check_state(*sys.argv[2:5])
        return
    src, frames, plugin, work = sys.argv[1:5]
    scripts = os.path.join(src, "vtkfilters", "scripts")
    view = os.path.join(scripts, "hexdem_view.py")
    pvbatch = os.path.join(src, "scripts", "pvbatch-xvfb.sh")
    os.makedirs(work, exist_ok=True)
    state, png = os.path.join(work, "series.pvsm"), os.path.join(work, "view.png")
    for path in (state, png):
        if os.path.exists(path):
            os.remove(path)
    r = run([pvbatch, view, os.path.join(frames, "series.pvd"), "-o", state, "--screenshot", png,
             "--plugin", plugin])
    check(r.returncode == 0, "hexdem_view.py: exit %d\n%s%s" % (r.returncode, r.stdout, r.stderr))
    check("paraview --state=" + state in r.stdout, "no GUI command printed: %s" % r.stdout)
    check(os.path.isfile(state), "no state file")
    r = run([sys.executable, os.path.join(src, "tests", "cli", "check_png.py"), png, "1280", "960", "5", "0.2"])
    check(r.returncode == 0, "screenshot: %s%s" % (r.stdout, r.stderr))
    r = run([pvbatch, os.path.abspath(__file__), "--check", state, plugin, scripts])
    sys.stdout.write(r.stdout)
    check(r.returncode == 0 and "OK: plugin defaults" in r.stdout, "state check: exit %d\n%s" % (r.returncode, r.stderr))

    # Bad input: exit 2, one line naming it, no state file.
    bad = os.path.join(work, "bad.pvsm")
    for args, part in (([os.path.join(work, "missing.pvd")], "missing.pvd"),
                       ([os.path.join(frames, "series.pvd"), "--body", "nose"], "'nose'"),
                       ([os.path.join(frames, "bad", "no_state.vtu")], "'state'")):
        r = run([pvbatch, view] + args + ["-o", bad, "--plugin", plugin])
        # (Lines of pvbatch-xvfb.sh itself, retrying a busy X server, are not the script's.)
        lines = [line for line in r.stderr.splitlines()
                 if line.strip() and not line.startswith("pvbatch-xvfb:")]
        check(r.returncode == 2, "%s: exit %d, expected 2 (%s)" % (args, r.returncode, r.stderr))
        check(len(lines) == 1 and part in lines[0], "%s: stderr %r" % (args, r.stderr))
        check(not os.path.exists(bad), "%s: a state file was written" % args)
    print("OK: hexdem_view.py")


if __name__ == "__main__":
    main()

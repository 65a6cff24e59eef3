"""Opens a hexdem result series in ParaView the way docs/filters.md (section 5) describes: the
disks at their true size coloured by the maximum shear stress, the cracks on top coloured by
mode, the fragments (hidden until switched on) and the fragment table in a spreadsheet.

    pvpython vtkfilters/scripts/hexdem_view.py run.pvd [-o run.pvsm] [--time T] [--body NAME]
             [--screenshot PNG] [--plugin PATH] [--open]

writes a ParaView state file (default: the input's name with .pvsm, in the current folder)
and prints how to open it in the GUI:

    PV_PLUGIN_PATH=build/release/lib/paraview-5.11/plugins/HexDEMFilters paraview --state=run.pvsm

(`--open` starts that GUI itself). The state holds:

- *Disks*: HexDEM Max Shear Stress on the series, Point Gaussian splats of radius `radius`
  (plain circles), coloured by max_shear_ratio (max_shear [Pa] without p_max); the colour range
  is 0 to the largest value over the series and grows with the time steps after that (never
  fixed to the zeros or round-off of t = 0).
- *Cracks*: HexDEM Crack Map, lines coloured by the categorical `mode`: tension red, shear
  blue, compression green (the figure scripts' colours), drawn above the disks.
- *Fragments*: HexDEM Fragment Counter (of one body with --body), Point Gaussian coloured by
  the categorical `fragment_id` (12 colours, then grey), hidden; its table in a spreadsheet
  view beside the render view.

A missing input, an input that is not a hexdem frame, or an unknown --body gives one line on
stderr and exit code 2, with no state file written.
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import figure_common as fc  # noqa: E402

SCRIPT = "hexdem_view.py"
# Fragments with a colour (and a legend entry) of their own.
FRAGMENT_COLOURS = 12


def error(message):
    sys.stderr.write("%s: error: %s\n" % (SCRIPT, message))
    sys.exit(2)


def parse(argv):
    parser = argparse.ArgumentParser(description="Open a hexdem series in ParaView (state file).")
    parser.add_argument("input", help="hexdem result series (.pvd) or frame (.vtu)")
    parser.add_argument("-o", "--state", help="state file to write (default: <input name>.pvsm)")
    parser.add_argument("--time", type=float, help="time shown [s] (default: the last frame)")
    parser.add_argument("--body", help="count the fragments of this body only (e.g. target)")
    parser.add_argument("--screenshot", help="also render the view to this PNG")
    parser.add_argument("--plugin", help="path of HexDEMFilters.so (default: as the figure scripts)")
    parser.add_argument("--open", action="store_true", help="start the ParaView GUI on the state")
    args = parser.parse_args(argv)
    if not os.path.isfile(args.input):
        error("input file '%s' does not exist" % args.input)
    if not args.input.lower().endswith((".pvd", ".vtu")):
        error("input '%s' is neither a .pvd series nor a .vtu frame" % args.input)
    if args.state is None:
        args.state = os.path.splitext(os.path.basename(args.input))[0] + ".pvsm"
    if not args.state.lower().endswith(".pvsm"):
        error("-o: the state file must end in .pvsm (got '%s')" % args.state)
    for path in [args.state] + ([args.screenshot] if args.screenshot else []):
        folder = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(folder):
            error("folder '%s' of '%s' does not exist" % (folder, path))
    return args


def series_times(reader):
    """The times of a series' frames ([0] for a single frame)."""
    values = getattr(reader, "TimestepValues", None)
    if values is None:
        return [0.0]
    return [float(values)] if isinstance(values, (int, float)) else (list(values) or [0.0])


def show_disks(pv, source, view, r_max):
    disks = fc.show_disks(pv, source, view, r_max)
    disks.SetScalarBarVisibility(view, True)
    return disks


def main(argv):
    args = parse(argv)
    from paraview import servermanager
    from paraview import simple as pv
    try:  # fc.fail's one-line messages, with the exit code of bad input
        fc.load_plugin(SCRIPT, pv, args.plugin)
        reader, data, time = fc.open_input(SCRIPT, pv, args.input, args.time)
    except SystemExit as e:
        sys.exit(2 if e.code == 1 else e.code)
    if data.GetCellData().GetArray("state") is None:
        error("'%s' has no 'state' cell array (not a hexdem result frame?)" % args.input)
    if args.body:
        names = data.GetFieldData().GetAbstractArray("body_names")
        known = [names.GetValue(k) for k in range(names.GetNumberOfValues())] if names else []
        if args.body not in known:
            error("--body: '%s' has no body '%s' (bodies: %s)" % (
                args.input, args.body, ", ".join(known) if known else "no body_names field data"))
    pv.RenameSource(os.path.basename(args.input), reader)
    r_max = data.GetPointData().GetArray("radius").GetRange()[1]

    layout = pv.CreateLayout("hexdem")
    view = fc.make_view(pv, (1280, 960), time)
    view.InteractionMode = "2D"
    pv.AssignViewToLayout(view=view, layout=layout, hint=0)

    # Disks: max shear stress, true size.
    shear = pv.HexDEMMaxShearStress(Input=reader)
    pv.RenameSource("Disks (max shear)", shear)
    shear.UpdatePipeline(time)
    out = servermanager.Fetch(shear)
    array = "max_shear_ratio" if out.GetPointData().GetArray("max_shear_ratio") else "max_shear"
    disks = show_disks(pv, shear, view, r_max)
    pv.ColorBy(disks, ("POINTS", array))
    lut = pv.GetColorTransferFunction(array)
    lut.ApplyPreset("Turbo", True)
    # The range: 0 to the largest value over the whole series (from ParaView's data
    # information, one pipeline update per frame), growing with the time steps after that. A
    # frame at t = 0 holds zeros or round-off only, and ParaView's default keeps the first
    # range it saw.
    high = 0.0
    for t in series_times(reader):
        shear.UpdatePipeline(t)
        high = max(high, shear.PointData[array].GetRange()[1])
    shear.UpdatePipeline(time)
    lut.RescaleTransferFunction(0.0, high if high > 0 else 1.0)
    lut.AutomaticRescaleRangeMode = "Grow and update every timestep"
    fc.style_scalar_bar(pv, lut, view, "tau_max / p_max" if array == "max_shear_ratio" else "tau_max [Pa]")

    # Cracks: categorical mode, above the disks.
    cracks = pv.HexDEMCrackMap(Input=reader)
    pv.RenameSource("Cracks", cracks)
    lines = pv.Show(cracks, view)
    lines.SetRepresentationType("Surface")
    mode_lut = pv.GetColorTransferFunction("mode")
    fc.categorical_modes(mode_lut)
    # Not ColorBy: it would rescale the (categorical) map to the data, of which a frame
    # without cracks has none.
    lines.ColorArrayName = ["CELLS", "mode"]
    lines.LookupTable = mode_lut
    lines.LineWidth = 2.0
    lines.Position = [0.0, 0.0, 0.01 * r_max]
    bar = fc.style_scalar_bar(pv, mode_lut, view, "crack mode", categorical=True)
    bar.Position = [0.84, 0.72]
    bar.ScalarBarLength = 0.2
    lines.SetScalarBarVisibility(view, True)

    # Fragments: categorical fragment_id, hidden; the table in a spreadsheet.
    fragments = pv.HexDEMFragmentCounter(Input=reader)
    pv.RenameSource("Fragments", fragments)
    if args.body:
        fragments.BodyName = args.body
    pieces = pv.Show(fragments, view)
    pieces.SetRepresentationType("Point Gaussian")
    pieces.ShaderPreset = "Plain circle"
    pieces.GaussianRadius = 1.0
    pieces.ScaleByArray = 1
    pieces.SetScaleArray = ["POINTS", "radius"]
    pieces.UseScaleFunction = 0
    pv.ColorBy(pieces, ("POINTS", "fragment_id"))
    fc.categorical_fragments(pv.GetColorTransferFunction("fragment_id"),
                             [str(k) for k in range(FRAGMENT_COLOURS)])
    pv.Hide(fragments, view)
    table_view = pv.CreateView("SpreadSheetView")
    table_view.ViewTime = time
    pv.AssignViewToLayout(view=table_view, layout=layout, hint=0)
    layout.SetSplitFraction(0, 0.7)
    pv.Show(pv.OutputPort(fragments, 1), table_view)

    pv.SetActiveView(view)
    pv.SetActiveSource(shear)
    camera = fc.Camera(fc.frame_box(data, None), (1280, 960), 0.16)
    camera.apply(pv, view)
    scene = pv.GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.AnimationTime = time
    if args.screenshot:
        pv.SaveScreenshot(args.screenshot, view, ImageResolution=[1280, 960])
    pv.SaveState(args.state)
    if not os.path.isfile(args.state):
        sys.stderr.write("%s: could not write '%s'\n" % (SCRIPT, args.state))
        sys.exit(1)
    plugin_dir = os.path.dirname(fc.loaded_plugin_path() or "")
    command = "PV_PLUGIN_PATH=%s paraview --state=%s" % (plugin_dir, args.state)
    print("hexdem view: %s (t = %g s) -> %s\n  open it: %s" % (args.input, time, args.state, command))
    if args.open:
        env = dict(os.environ)
        env["PV_PLUGIN_PATH"] = plugin_dir
        os.execvpe("paraview", ["paraview", "--state=" + args.state], env)


if __name__ == "__main__":
    main(sys.argv[1:])

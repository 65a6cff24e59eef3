"""Renders the crack map of a hexdem frame: the disks in light grey at their true size and
the cracks (HexDEM Crack Map filter: one segment per broken bond, where the two disks' cells
meet, merged into polylines) coloured by failure mode.

    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch figure_cracks.py RUN.pvd OUT.png \
        [--time T] [--zoom X0 Y0 X1 Y1] [--max-break-time T] [--line-width PX] \
        [--disks grey|damage|none] [--size W H] [--plugin PATH] [--title TEXT]
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import figure_common as fc  # noqa: E402

SCRIPT = "figure_cracks"
LEGEND = 0.22  # right fraction of the image kept for the legend
MODES = fc.CRACK_MODES


def main(argv):
    parser = fc.argument_parser("Render the crack map of a hexdem frame to a PNG.")
    parser.add_argument("--max-break-time", type=float,
                        help="only bonds broken at or before this time [s]")
    parser.add_argument("--line-width", type=float, default=0.0,
                        help="crack line width in pixels (default: from the disk size on screen)")
    parser.add_argument("--disks", choices=("grey", "damage", "none"), default="grey",
                        help="how to draw the disks under the cracks (default grey)")
    args = parser.parse_args(argv)
    fc.check_arguments(SCRIPT, args)

    from paraview import simple as pv
    fc.load_plugin(SCRIPT, pv, args.plugin)
    reader, data, time = fc.open_input(SCRIPT, pv, args.input, args.time)
    if data.GetCellData().GetArray("state") is None:
        fc.fail(SCRIPT, "'%s' has no 'state' cell array (not a hexdem result frame?)" % args.input)

    cracks = pv.HexDEMCrackMap(Input=reader)
    if args.max_break_time is not None:
        cracks.UseMaxBreakTime = 1
        cracks.MaxBreakTime = args.max_break_time
    fc.update_filter(SCRIPT, cracks, time, args.input)
    out = cracks.GetClientSideObject().GetOutputDataObject(0)
    counts = {name: int(fc.field_value(out, "crack_count_" + name, 0)) for _, name, _ in MODES}
    total = int(fc.field_value(out, "crack_count", 0))
    length = fc.field_value(out, "crack_length", 0.0)

    view = fc.make_view(pv, args.size, time)
    r_max = data.GetPointData().GetArray("radius").GetRange()[1]
    camera = fc.Camera(fc.frame_box(data, args.zoom), args.size, LEGEND)
    if args.disks != "none":
        disks = fc.show_disks(pv, reader, view, r_max)
        if args.disks == "damage" and data.GetPointData().GetArray("damage") is not None:
            pv.ColorBy(disks, ("POINTS", "damage"))
            lut = pv.GetColorTransferFunction("damage")
            lut.AutomaticRescaleRangeMode = "Never"
            # Light grey for intact disks to dark grey for disks with every bond broken.
            lut.RGBPoints = [0.0, 0.85, 0.85, 0.85, 1.0, 0.25, 0.25, 0.25]
            disks.SetScalarBarVisibility(view, False)
        else:
            disks.ColorArrayName = ["POINTS", ""]
            disks.AmbientColor = [0.82, 0.82, 0.82]
            disks.DiffuseColor = [0.82, 0.82, 0.82]

    lines = pv.Show(cracks, view)
    lines.SetRepresentationType("Surface")
    pv.ColorBy(lines, ("CELLS", "mode"))
    lut = pv.GetColorTransferFunction("mode")
    fc.categorical_modes(lut, counts)
    width = args.line_width or min(6.0, max(1.5, 0.35 * r_max * camera.pixels_per_metre))
    lines.LineWidth = width
    lines.RenderLinesAsTubes = 0
    lines.Position = [0.0, 0.0, 1e-3 * camera.depth]  # above the disks (camera looks down -z)
    fc.style_scalar_bar(pv, lut, view, "broken bonds", LEGEND, categorical=True)
    lines.SetScalarBarVisibility(view, True)

    title = args.title or "cracks   %s,  %s:  %d broken bonds, %.4g m" % (
        os.path.basename(args.input), fc.format_time(time), total, length)
    fc.finish(SCRIPT, pv, view, camera, title, args.output, args.size)


if __name__ == "__main__":
    # No sys.exit(0) on success: see figure_max_shear.py.
    main(sys.argv[1:])

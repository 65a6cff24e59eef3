"""Renders the fragments of a hexdem frame (HexDEM Fragment Counter filter: disks connected
by intact bonds): every disk at its true size, coloured by its fragment. The largest
fragments get distinct colours and a legend entry with their number of disks; the smaller
ones (beyond --colours, or below --min-disks) are grey.

    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch figure_fragments.py RUN.pvd OUT.png \
        [--time T] [--zoom X0 Y0 X1 Y1] [--min-disks N] [--colours N] [--size W H] \
        [--plugin PATH] [--title TEXT]
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import figure_common as fc  # noqa: E402

SCRIPT = "figure_fragments"
LEGEND = 0.22
SMALL_COLOUR = [0.78, 0.78, 0.78]


def main(argv):
    parser = fc.argument_parser("Render the fragments of a hexdem frame to a PNG.")
    parser.add_argument("--min-disks", type=int, default=2,
                        help="fragments with fewer disks are grey and not counted (default 2)")
    parser.add_argument("--colours", type=int, default=12,
                        help="number of largest fragments with their own colour (default 12)")
    args = parser.parse_args(argv)
    fc.check_arguments(SCRIPT, args)
    if args.min_disks < 1 or args.colours < 1:
        fc.fail(SCRIPT, "--min-disks and --colours must be >= 1")

    from paraview import servermanager
    from paraview import simple as pv
    fc.load_plugin(SCRIPT, pv, args.plugin)
    reader, data, time = fc.open_input(SCRIPT, pv, args.input, args.time)
    if data.GetCellData().GetArray("state") is None:
        fc.fail(SCRIPT, "'%s' has no 'state' cell array (not a hexdem result frame?)" % args.input)

    fragments = pv.HexDEMFragmentCounter(Input=reader)
    fragments.MinimumDisks = args.min_disks
    fc.update_filter(SCRIPT, fragments, time, args.input)
    out = fragments.GetClientSideObject().GetOutputDataObject(0)
    table = servermanager.Fetch(fragments, idx=1)
    count = int(fc.field_value(out, "fragment_count", 0))
    total = int(fc.field_value(out, "fragment_count_total", 0))
    coloured = min(count, args.colours)
    sizes = [table.GetValueByName(k, "disks").ToInt() for k in range(coloured)]

    view = fc.make_view(pv, args.size, time)
    r_max = data.GetPointData().GetArray("radius").GetRange()[1]
    camera = fc.Camera(fc.frame_box(data, args.zoom), args.size, LEGEND)
    disks = fc.show_disks(pv, fragments, view, r_max)
    pv.ColorBy(disks, ("POINTS", "fragment_id"))
    lut = pv.GetColorTransferFunction("fragment_id")
    fc.categorical_fragments(lut, ["%d: %d disks" % (k, sizes[k]) for k in range(coloured)])
    lut.NanColor = SMALL_COLOUR  # fragments without a colour of their own
    fc.style_scalar_bar(pv, lut, view, "fragment", LEGEND, categorical=True)
    disks.SetScalarBarVisibility(view, True)

    smaller = total - coloured
    title = args.title or "fragments   %s,  %s:  %d of %d+ disks%s" % (
        os.path.basename(args.input), fc.format_time(time), count, args.min_disks,
        " (%d smaller: grey)" % smaller if smaller else "")
    fc.finish(SCRIPT, pv, view, camera, title, args.output, args.size)


if __name__ == "__main__":
    # No sys.exit(0) on success: see figure_max_shear.py.
    main(sys.argv[1:])

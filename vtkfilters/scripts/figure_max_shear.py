"""Renders the maximum shear stress of a hexdem frame as in the paper's Figs. 4 and 5: every
disk at its true size coloured by tau_max / p_max (HexDEM Max Shear Stress filter), or by
tau_max [Pa] when no peak pressure is known.

    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch figure_max_shear.py RUN.pvd OUT.png \
        [--time T] [--zoom X0 Y0 X1 Y1] [--p-max P] [--3d] [--range LOW HIGH] \
        [--colormap NAME] [--size W H] [--plugin PATH] [--title TEXT]
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import figure_common as fc  # noqa: E402

SCRIPT = "figure_max_shear"


def main(argv):
    parser = fc.argument_parser("Render tau_max / p_max of a hexdem frame to a PNG.")
    parser.add_argument("--p-max", type=float, default=0.0,
                        help="peak pressure p_max [Pa] (default: the frame's p_max)")
    parser.add_argument("--3d", dest="three_d", action="store_true",
                        help="the 3D maximum shear (s_1 - s_3)/2, with s_zz")
    parser.add_argument("--range", nargs=2, type=float, metavar=("LOW", "HIGH"),
                        help="colour range (default: 0 to the largest value)")
    parser.add_argument("--colormap", default="Turbo", help="ParaView colour preset (Turbo)")
    args = parser.parse_args(argv)
    fc.check_arguments(SCRIPT, args)
    if args.p_max < 0:
        fc.fail(SCRIPT, "--p-max must be >= 0")

    from paraview import simple as pv
    fc.load_plugin(SCRIPT, pv, args.plugin)
    reader, data, time = fc.open_input(SCRIPT, pv, args.input, args.time)
    if data.GetPointData().GetArray("stress") is None and data.GetCellData().GetArray("normal_force") is None:
        fc.fail(SCRIPT, "'%s' has neither a 'stress' point array nor bond forces" % args.input)

    shear = pv.HexDEMMaxShearStress(Input=reader)
    shear.PMax = args.p_max
    shear.ComputeThreeDimensional = 1 if args.three_d else 0
    fc.update_filter(SCRIPT, shear, time, args.input)
    out = shear.GetClientSideObject().GetOutputDataObject(0)
    if out is None or out.GetNumberOfPoints() == 0:
        fc.fail(SCRIPT, "the maximum shear stress of '%s' could not be computed" % args.input)
    base = "max_shear_3d" if args.three_d else "max_shear"
    has_ratio = out.GetPointData().GetArray(base + "_ratio") is not None
    array = base + "_ratio" if has_ratio else base
    label = ("tau_max,3D" if args.three_d else "tau_max") + (" / p_max" if has_ratio else " [Pa]")

    view = fc.make_view(pv, args.size, time)
    r_max = data.GetPointData().GetArray("radius").GetRange()[1]
    camera = fc.Camera(fc.frame_box(data, args.zoom), args.size)
    disks = fc.show_disks(pv, shear, view, r_max)
    pv.ColorBy(disks, ("POINTS", array))
    lut = pv.GetColorTransferFunction(array)
    lut.ApplyPreset(args.colormap, True)
    low, high = args.range if args.range else (0.0, out.GetPointData().GetArray(array).GetRange()[1])
    lut.RescaleTransferFunction(low, high if high > low else low + 1e-12)
    lut.AutomaticRescaleRangeMode = "Never"
    fc.style_scalar_bar(pv, lut, view, label)
    disks.SetScalarBarVisibility(view, True)

    title = args.title or "%s   %s,  %s" % (label, os.path.basename(args.input), fc.format_time(time))
    fc.finish(SCRIPT, pv, view, camera, title, args.output, args.size)


if __name__ == "__main__":
    # No sys.exit(0) on success: raising SystemExit inside pvbatch after rendering makes its
    # shutdown fail with a GLX error and exit code 1.
    main(sys.argv[1:])

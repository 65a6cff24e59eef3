"""The half-plane's Fig. 4 with the waves labelled: tau_max / p_max at t = 104 us (HexDEM Max
Shear Stress filter, every disk at its true size) with the fronts the continuum theory
predicts at that time drawn over it: the quasi-longitudinal (qP) and quasi-transverse (qS)
fronts of the strip load, the von Schmidt head wave joining them, and the extent of the
Rayleigh pulse on the surface (analyze.front_curves).

    scripts/pvbatch-xvfb.sh cases/halfplane/figure_fronts.py RUN.pvd OUT.png [--time T]
        [--range LOW HIGH] [--size W H] [--plugin PATH] [--title TEXT] [--zoom X0 Y0 X1 Y1]
"""

import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "..", "vtkfilters", "scripts"))

import figure_common as fc  # noqa: E402
sys.path.insert(0, os.path.join(HERE, ".."))
from run_status import require_completed  # noqa: E402

SCRIPT = "figure_fronts"
MATERIAL_B = ((5.0961e9, 1.2256e9, 3.5359e9, 1.2198e9), 1244.0)  # case.toml: Pa, kg/m^3
A = 0.02  # m: half-width of the loaded strip


def main(argv):
    parser = fc.argument_parser("Render tau_max / p_max of the half-plane with the predicted wave fronts.")
    parser.add_argument("--range", nargs=2, type=float, default=(0.0, 0.3), metavar=("LOW", "HIGH"),
                        help="colour range (default 0 0.3)")
    args = parser.parse_args(argv)
    fc.check_arguments(SCRIPT, args)
    require_completed(args.input, SCRIPT)

    import analyze  # numpy; the front geometry
    from paraview import simple as pv
    fc.load_plugin(SCRIPT, pv, args.plugin)
    reader, data, time = fc.open_input(SCRIPT, pv, args.input, 104e-6 if args.time is None else args.time)
    shear = pv.HexDEMMaxShearStress(Input=reader)
    shear.UpdatePipeline(time)
    out = shear.GetClientSideObject().GetOutputDataObject(0)
    if out is None or out.GetPointData().GetArray("max_shear_ratio") is None:
        fc.fail(SCRIPT, "'%s' has no p_max: cannot form tau_max / p_max" % args.input)

    view = fc.make_view(pv, args.size, time)
    r_max = data.GetPointData().GetArray("radius").GetRange()[1]
    camera = fc.Camera(fc.frame_box(data, args.zoom), args.size)
    disks = fc.show_disks(pv, shear, view, r_max)
    pv.ColorBy(disks, ("POINTS", "max_shear_ratio"))
    lut = pv.GetColorTransferFunction("max_shear_ratio")
    lut.ApplyPreset("Turbo", True)
    lut.RescaleTransferFunction(args.range[0], args.range[1])
    lut.AutomaticRescaleRangeMode = "Never"
    fc.style_scalar_bar(pv, lut, view, "tau_max / p_max")
    disks.SetScalarBarVisibility(view, True)

    curves = analyze.front_curves(MATERIAL_B[0], MATERIAL_B[1], A, time)
    width, height = args.size

    def to_view(x, y):  # world [m] -> normalised view position, for the labels
        return [0.5 + (x - camera.cx) * camera.pixels_per_metre / width,
                0.5 + (y - camera.cy) * camera.pixels_per_metre / height]

    styles = {"qP": ([1, 1, 1], 2.0), "qS": ([1, 1, 1], 2.0), "head": ([1, 0.2, 0.8], 2.5),
              "rayleigh": ([1, 0.2, 0.8], 6.0)}
    for key, pts in curves.items():
        line = pv.PolyLineSource(Points=[v for x, y in pts for v in (x, y, 1e-3)])
        shown = pv.Show(line, view)
        shown.ColorArrayName = ["POINTS", ""]
        shown.AmbientColor = shown.DiffuseColor = styles[key][0]
        shown.LineWidth = styles[key][1]
        shown.RenderLinesAsTubes = 0
    qp, qs, head, ray = curves["qP"], curves["qS"], curves["head"], curves["rayleigh"]
    mid = len(qp) // 2
    labels = [
        ("qP (quasi-longitudinal)", qp[mid][0] + 0.004, qp[mid][1] - 0.004),
        ("qS (quasi-transverse)", qs[mid + 20][0] + 0.003, qs[mid + 20][1] - 0.004),
        ("von Schmidt head wave", 0.5 * (head[0][0] + head[1][0]) + 0.006, 0.5 * (head[0][1] + head[1][1])),
        ("Rayleigh", ray[0][0], 0.006),
    ]
    for text, x, y in labels:
        label = pv.Text(Text=text)
        shown = pv.Show(label, view)
        shown.WindowLocation = "Any Location"
        shown.Position = to_view(x, y)
        shown.Color = [0.0, 0.0, 0.0]
        shown.FontSize = 15
        shown.Bold = 1
        shown.ShowBorder = "Always"
        shown.BackgroundColor = [1.0, 1.0, 1.0, 0.7]
    title = args.title or "tau_max / p_max at %s, predicted fronts: qP, qS, head wave, Rayleigh" % fc.format_time(time)
    fc.finish(SCRIPT, pv, view, camera, title, args.output, args.size)


if __name__ == "__main__":
    # No sys.exit(0) on success: raising SystemExit inside pvbatch after rendering makes its
    # shutdown fail with a GLX error and exit code 1.
    main(sys.argv[1:])

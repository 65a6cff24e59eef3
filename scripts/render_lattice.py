"""Renders a hexdem lattice (.vtu) to a PNG: disks at their true size, bonds as thin lines.

Run with ParaView's pvbatch under a virtual X display:

    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch scripts/render_lattice.py IN.vtu OUT.png \
        [--color kind|body|material|cell_area|radius|ring_radius|<set name>] \
        [--zoom x0 y0 x1 y1] [--bonds auto|on|off] [--size W H]

The disks are drawn with the `Point Gaussian` representation, scaled by the `radius` point
array with no transfer function (GaussianRadius 1, so a disk of radius r is drawn with radius
r in model units). `--zoom` frames the box [x0, x1] x [y0, y1] (metres) to show individual
disks. Bonds are drawn on top of the disks as thin dark lines; with `--bonds auto` (default)
only when a disk spans at least 6 pixels, since finer bonds only grey the picture out.
Categorical arrays (kind, body, material, boundary sets) get a discrete legend; body names
come from the `body_names` field data.
"""

import argparse
import os
import sys

CATEGORICAL = {"kind", "body", "material"}
KIND_NAMES = {0: "disk", 1: "semi-disk"}
# Colours for categories (Paul Tol's bright scheme), then repeated.
PALETTE = [
    (0.27, 0.47, 0.67), (0.93, 0.40, 0.47), (0.13, 0.53, 0.20), (0.80, 0.73, 0.27),
    (0.40, 0.80, 0.93), (0.67, 0.20, 0.47), (0.73, 0.73, 0.73),
]


def fail(message):
    """Prints a one-line error and exits with a non-zero code."""
    sys.stderr.write("render_lattice: %s\n" % message)
    sys.exit(1)


def parse_arguments(argv):
    parser = argparse.ArgumentParser(description="Render a hexdem lattice .vtu to a PNG.")
    parser.add_argument("input", help="lattice .vtu file")
    parser.add_argument("output", help="PNG file to write")
    parser.add_argument("--color", default="kind",
                        help="point array to colour by (default: kind)")
    parser.add_argument("--zoom", nargs=4, type=float, metavar=("X0", "Y0", "X1", "Y1"),
                        help="show only this box [m]")
    parser.add_argument("--bonds", choices=("auto", "on", "off"), default="auto",
                        help="draw bonds (auto: only when disks are large enough on screen)")
    parser.add_argument("--size", nargs=2, type=int, default=(1280, 960), metavar=("W", "H"),
                        help="image size in pixels (default 1280 960)")
    return parser.parse_args(argv)


def point_arrays(data):
    pd = data.GetPointData()
    return [pd.GetArrayName(k) for k in range(pd.GetNumberOfArrays())]


def field_strings(data, name):
    array = data.GetFieldData().GetAbstractArray(name)
    if array is None or not array.IsA("vtkStringArray"):
        return []
    return [array.GetValue(k) for k in range(array.GetNumberOfValues())]


def category_labels(name, values, data):
    """Legend labels for the integer values of a categorical array."""
    if name == "kind":
        return [KIND_NAMES.get(v, str(v)) for v in values]
    if name == "body":
        bodies = field_strings(data, "body_names")
        return [bodies[v] if 0 <= v < len(bodies) else "body %d" % v for v in values]
    if name == "material":
        return ["material %d" % v for v in values]
    return ["outside" if v == 0 else "in set" for v in values]


def main(argv):
    args = parse_arguments(argv)
    if not os.path.isfile(args.input):
        fail("input file '%s' does not exist" % args.input)
    out_dir = os.path.dirname(os.path.abspath(args.output))
    if not os.path.isdir(out_dir):
        fail("output folder '%s' does not exist" % out_dir)
    if args.zoom and (args.zoom[2] <= args.zoom[0] or args.zoom[3] <= args.zoom[1]):
        fail("--zoom needs x0 < x1 and y0 < y1")

    import numpy
    from paraview import simple as pv
    from vtkmodules.util.numpy_support import vtk_to_numpy

    reader = pv.XMLUnstructuredGridReader(FileName=[args.input])
    reader.UpdatePipeline()
    # pvbatch runs a built-in server: use the reader's output in place instead of a copy.
    data = reader.GetClientSideObject().GetOutputDataObject(0)
    if data is None or data.GetNumberOfPoints() == 0:
        fail("'%s' has no disks" % args.input)
    arrays = point_arrays(data)
    if "radius" not in arrays:
        fail("'%s' has no 'radius' point array (not a lattice file?)" % args.input)
    if args.color not in arrays:
        fail("'%s' has no point array '%s' (available: %s)"
             % (args.input, args.color, ", ".join(arrays)))

    width, height = args.size
    view = pv.CreateView("RenderView")
    view.ViewSize = [width, height]
    view.Background = [1.0, 1.0, 1.0]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.OrientationAxesVisibility = 0
    view.CameraParallelProjection = 1

    # Camera: the whole lattice (with its disks) or the zoom box, centred, aspect kept.
    bounds = data.GetBounds()
    r_max = data.GetPointData().GetArray("radius").GetRange()[1]
    if args.zoom:
        x0, y0, x1, y1 = args.zoom
    else:
        x0, x1 = bounds[0] - r_max, bounds[1] + r_max
        y0, y1 = bounds[2] - r_max, bounds[3] + r_max
    # The legend takes the right of the image and the title its top: fit the box in the rest.
    usable_w, usable_h = 0.84 * width, height - 50.0
    pixels_per_metre = min(usable_w / (x1 - x0), usable_h / (y1 - y0)) / 1.04
    half_height = 0.5 * height / pixels_per_metre
    cx = 0.5 * (x0 + x1) + 0.5 * (width - usable_w) / pixels_per_metre
    cy = 0.5 * (y0 + y1) + 0.5 * (height - usable_h) / pixels_per_metre

    # Disks: Point Gaussian splats of radius GaussianRadius * radius (no transfer function).
    disks = pv.Show(reader, view)
    disks.SetRepresentationType("Point Gaussian")
    disks.ShaderPreset = "Plain circle"
    disks.GaussianRadius = 1.0
    disks.ScaleByArray = 1
    disks.SetScaleArray = ["POINTS", "radius"]
    disks.UseScaleFunction = 0
    disks.ScaleTransferFunction.Points = [0.0, 0.0, 0.5, 0.0, r_max, r_max, 0.5, 0.0]
    disks.Emissive = 0

    pv.ColorBy(disks, ("POINTS", args.color))
    lut = pv.GetColorTransferFunction(args.color)
    values = data.GetPointData().GetArray(args.color)
    low, high = values.GetRange()
    set_names = [a for a in arrays if a not in ("radius", "kind", "cell_area", "body", "material",
                                                "ring_radius")]
    if args.color in CATEGORICAL or args.color in set_names:
        present = [int(v) for v in numpy.unique(vtk_to_numpy(values))]
        if args.color in set_names:
            present = [0, 1]
        labels = category_labels(args.color, present, data)
        lut.InterpretValuesAsCategories = 1
        lut.Annotations = [x for v, label in zip(present, labels) for x in (str(v), label)]
        lut.IndexedColors = [c for k in range(len(present)) for c in PALETTE[k % len(PALETTE)]]
        if args.color in set_names:
            lut.IndexedColors = [0.80, 0.80, 0.80, 0.85, 0.20, 0.15]
    else:
        lut.ApplyPreset("Viridis (matplotlib)", True)
        lut.RescaleTransferFunction(low, high if high > low else low + 1.0)
    units = {"cell_area": " [m^2]", "radius": " [m]", "ring_radius": " [m]"}
    bar = pv.GetScalarBar(lut, view)
    bar.Title = args.color + units.get(args.color, "")
    bar.ComponentTitle = ""
    bar.TitleColor = [0.0, 0.0, 0.0]
    bar.LabelColor = [0.0, 0.0, 0.0]
    bar.TitleFontSize = 16
    bar.LabelFontSize = 14
    bar.WindowLocation = "Any Location"
    bar.Position = [0.89, 0.1]
    bar.ScalarBarLength = 0.6
    bar.DrawBackground = 1  # readable over disks in a zoomed view
    bar.BackgroundColor = [1.0, 1.0, 1.0, 1.0]
    bar.BackgroundPadding = 6.0
    disks.SetScalarBarVisibility(view, True)

    # Bonds: thin dark lines just above the disks (the camera looks down -z).
    draw_bonds = args.bonds == "on" or (args.bonds == "auto" and 2.0 * r_max * pixels_per_metre >= 6.0)
    if draw_bonds and data.GetNumberOfCells() > 0:
        # A second pipeline object: Show(reader) again would return the disks' representation.
        lines = pv.PassArrays(Input=reader)
        bonds = pv.Show(lines, view)
        bonds.SetRepresentationType("Wireframe")
        pv.ColorBy(bonds, None)
        bonds.AmbientColor = [0.15, 0.15, 0.15]
        bonds.DiffuseColor = [0.15, 0.15, 0.15]
        bonds.LineWidth = 1.0
        bonds.Opacity = 0.7
        bonds.Position = [0.0, 0.0, 1e-3 * max(x1 - x0, y1 - y0)]

    title = pv.Text(Text=os.path.basename(args.input) + ("   (detail)" if args.zoom else ""))
    title_display = pv.Show(title, view)
    title_display.WindowLocation = "Upper Center"
    title_display.Color = [0.0, 0.0, 0.0]
    title_display.FontSize = 18
    title_display.ShowBorder = "Always"
    title_display.BorderColor = [1.0, 1.0, 1.0]
    title_display.BackgroundColor = [1.0, 1.0, 1.0, 1.0]

    # The first render resets the camera to the data: set ours after it.
    pv.Render(view)
    view.CameraPosition = [cx, cy, 10.0 * max(x1 - x0, y1 - y0)]
    view.CameraFocalPoint = [cx, cy, 0.0]
    view.CameraViewUp = [0.0, 1.0, 0.0]
    view.CameraParallelScale = half_height
    pv.Render(view)
    pv.SaveScreenshot(args.output, view, ImageResolution=[width, height],
                      OverrideColorPalette="WhiteBackground", TransparentBackground=0)
    if not os.path.isfile(args.output):
        fail("could not write '%s'" % args.output)


if __name__ == "__main__":
    # No sys.exit(0) on success: raising SystemExit inside pvbatch after rendering makes its
    # shutdown fail with a GLX error and exit code 1.
    main(sys.argv[1:])

"""Shared parts of the figure scripts (figure_max_shear.py, figure_cracks.py,
figure_fragments.py): arguments, loading the HexDEMFilters plugin, opening a frame or a
series at a time, the render view, the camera, the title and the PNG.

Run the figure scripts with pvbatch under a virtual X display, e.g.

    xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch figure_cracks.py run.pvd cracks.png --time 1e-4
"""

import argparse
import glob
import os
import sys

SCRIPT_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(os.path.dirname(SCRIPT_DIR))
PLUGIN_NAME = "HexDEMFilters"

# Colours for categories (Paul Tol's bright and muted schemes), repeated when needed.
PALETTE = [
    (0.27, 0.47, 0.67), (0.93, 0.40, 0.47), (0.13, 0.53, 0.20), (0.80, 0.73, 0.27),
    (0.40, 0.80, 0.93), (0.67, 0.20, 0.47), (0.20, 0.13, 0.53), (0.53, 0.80, 0.93),
    (0.27, 0.67, 0.60), (0.07, 0.47, 0.20), (0.60, 0.60, 0.20), (0.53, 0.13, 0.33),
]


# Crack modes (the crack map's `mode`, the frames' `state`): code, name, colour. The figure
# scripts and hexdem_view.py colour cracks with these.
CRACK_MODES = [(2, "tension", (0.85, 0.15, 0.10)), (3, "shear", (0.10, 0.35, 0.85)),
               (4, "compression", (0.10, 0.60, 0.20))]
# Fragments without a colour of their own (beyond the palette, or outside a body selection).
SMALL_FRAGMENT_COLOUR = [0.75, 0.75, 0.75]


def categorical_modes(lut, counts=None):
    """Makes `lut` (the `mode` colour map) categorical: tension, shear, compression in the
    CRACK_MODES colours, with the count of each in its label when `counts` is given."""
    lut.InterpretValuesAsCategories = 1
    lut.AnnotationsInitialized = 1
    lut.Annotations = [x for mode, name, _ in CRACK_MODES for x in (
        str(mode), "%s (%d)" % (name, counts[name]) if counts else name)]
    lut.IndexedColors = [c for _, _, colour in CRACK_MODES for c in colour]


def categorical_fragments(lut, labels):
    """Makes `lut` (the `fragment_id` colour map) categorical: fragment k gets PALETTE[k] and
    the label labels[k]; other ids (smaller fragments, -1 outside a body selection) grey."""
    lut.InterpretValuesAsCategories = 1
    lut.AnnotationsInitialized = 1
    lut.Annotations = [x for k, label in enumerate(labels) for x in (str(k), label)]
    lut.IndexedColors = [c for k in range(len(labels)) for c in PALETTE[k % len(PALETTE)]]
    lut.NanColor = SMALL_FRAGMENT_COLOUR


def fail(script, message):
    """Prints a one-line error and exits with a non-zero code."""
    sys.stderr.write("%s: %s\n" % (script, message))
    sys.exit(1)


def argument_parser(description):
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("input", help="hexdem result series (.pvd) or frame (.vtu)")
    parser.add_argument("output", help="PNG file to write")
    parser.add_argument("--time", type=float,
                        help="time [s]: the series frame nearest to it (default: the last frame)")
    parser.add_argument("--zoom", nargs=4, type=float, metavar=("X0", "Y0", "X1", "Y1"),
                        help="show only this box [m]")
    parser.add_argument("--size", nargs=2, type=int, default=(1280, 960), metavar=("W", "H"),
                        help="image size in pixels (default 1280 960)")
    parser.add_argument("--plugin", help="path of %s.so (default: $HEXDEM_PLUGIN, the plugins "
                        "on PV_PLUGIN_PATH, or the build folders of this repository)" % PLUGIN_NAME)
    parser.add_argument("--title", help="title (default: file name and time)")
    return parser


def check_arguments(script, args):
    if not os.path.isfile(args.input):
        fail(script, "input file '%s' does not exist" % args.input)
    if not args.input.lower().endswith((".pvd", ".vtu")):
        fail(script, "input '%s' is neither a .pvd series nor a .vtu frame" % args.input)
    out_dir = os.path.dirname(os.path.abspath(args.output))
    if not os.path.isdir(out_dir):
        fail(script, "output folder '%s' does not exist" % out_dir)
    if args.zoom and (args.zoom[2] <= args.zoom[0] or args.zoom[3] <= args.zoom[1]):
        fail(script, "--zoom needs x0 < x1 and y0 < y1")


def load_plugin(script, pv, path):
    """Loads the plugin unless paraview.simple already has its filters (PV_PLUGIN_PATH)."""
    if hasattr(pv, "HexDEMCrackMap") and not path:
        return
    candidates = [path] if path else []
    if not path and os.environ.get("HEXDEM_PLUGIN"):
        candidates.append(os.environ["HEXDEM_PLUGIN"])
    if not candidates:
        pattern = os.path.join(REPO_DIR, "build", "*", "lib", "paraview-*", "plugins", PLUGIN_NAME,
                               PLUGIN_NAME + ".so")
        found = sorted(glob.glob(pattern), key=lambda p: ("/build/release/" not in p, p))
        candidates.extend(found[:1])
    if not candidates or not os.path.isfile(candidates[0]):
        fail(script, "cannot find the %s plugin (give --plugin PATH or set HEXDEM_PLUGIN)"
             % PLUGIN_NAME)
    pv.LoadPlugin(candidates[0], remote=False)
    if not hasattr(pv, "HexDEMCrackMap"):
        fail(script, "'%s' did not provide the hexdem filters" % candidates[0])
    LOADED_PLUGIN.append(os.path.abspath(candidates[0]))


LOADED_PLUGIN = []  # the plugin load_plugin loaded, if it did


def loaded_plugin_path():
    """The plugin's .so: the one load_plugin loaded, else the first on PV_PLUGIN_PATH."""
    if LOADED_PLUGIN:
        return LOADED_PLUGIN[-1]
    for folder in os.environ.get("PV_PLUGIN_PATH", "").split(os.pathsep):
        path = os.path.join(folder, PLUGIN_NAME + ".so")
        if folder and os.path.isfile(path):
            return os.path.abspath(path)
    return None


def check_series_frames(script, path):
    """Fails with one line naming the first frame a .pvd lists that is not a readable file
    (before VTK's reader prints a screenful of errors about it)."""
    import xml.etree.ElementTree as ElementTree
    try:
        root = ElementTree.parse(path).getroot()
    except (ElementTree.ParseError, OSError) as e:
        fail(script, "'%s' is not a readable .pvd series (%s)" % (path, e))
    folder = os.path.dirname(os.path.abspath(path))
    datasets = root.findall("./Collection/DataSet")
    if not datasets:
        fail(script, "'%s' lists no frames" % path)
    for dataset in datasets:
        name = dataset.get("file") or ""
        frame = name if os.path.isabs(name) else os.path.join(folder, name)
        if not os.path.isfile(frame):
            fail(script, "frame '%s' listed in '%s' does not exist" % (frame, path))


def first_outside(array, ok):
    """(tuple, component, value) of the first value of a vtkDataArray for which ok(value) is
    false, or None."""
    try:
        import numpy
        from vtkmodules.util.numpy_support import vtk_to_numpy
        values = vtk_to_numpy(array).reshape(array.GetNumberOfTuples(), -1)
        bad = numpy.argwhere(~ok(values))
        if len(bad) == 0:
            return None
        t, c = int(bad[0][0]), int(bad[0][1])
        return t, c, float(values[t, c])
    except ImportError:
        for t in range(array.GetNumberOfTuples()):
            for c in range(array.GetNumberOfComponents()):
                v = array.GetComponent(t, c)
                if not ok(v):
                    return t, c, v
        return None


def check_frame_values(script, path, data):
    """Fails with one line naming the frame, the array and the first bad value when the disk
    centres are not finite or a radius is not a finite number > 0 (not a frame of a run)."""
    import math
    try:
        import numpy
        finite, positive = numpy.isfinite, lambda v: numpy.isfinite(v) & (v > 0)
    except ImportError:
        finite, positive = math.isfinite, lambda v: math.isfinite(v) and v > 0
    for what, array, ok, expected in (
            ("'Points' array", data.GetPoints().GetData(), finite, "a finite number"),
            ("'radius' point array", data.GetPointData().GetArray("radius"), positive,
             "a finite number > 0")):
        bad = first_outside(array, ok)
        if bad is not None:
            fail(script, "'%s': the %s holds %g at tuple %d, component %d (expected %s)"
                 % (path, what, bad[2], bad[0], bad[1], expected))


def update_filter(script, proxy, time, path):
    """Runs a hexdem filter at `time`; when it refuses the frame, fails with its error message
    on one line (VTK's own reports are kept off the terminal), naming the input `path`."""
    import re
    from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow, vtkStringOutputWindow
    previous = vtkOutputWindow.GetInstance()
    previous_verbosity = vtkLogger.GetCurrentVerbosityCutoff()
    sink = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(sink)
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    try:
        proxy.UpdatePipeline(time)
    finally:
        vtkLogger.SetStderrVerbosity(previous_verbosity)
        vtkOutputWindow.SetInstance(previous)
    text = sink.GetOutput()
    # Reports look like "ERROR: In FILE, line N\nvtkClass (0x...): message\n\n".
    errors = [re.sub(r"^vtk\w+ \(0x[0-9a-fA-F]+\): ", "", block.split("\n", 1)[-1].strip())
              for block in text.split("\n\n") if block.strip().startswith("ERROR")]
    if errors:
        fail(script, "'%s': %s" % (path, " ".join(errors[0].split())))
    if text:
        sys.stderr.write(text)


def open_input(script, pv, path, time):
    """A reader for the frame or series, and the time [s] to show (snapped to a frame)."""
    if path.lower().endswith(".pvd"):
        check_series_frames(script, path)
        reader = pv.PVDReader(FileName=path)
        values = reader.TimestepValues  # a number for a single-frame series
        times = [float(values)] if isinstance(values, (int, float)) else list(values) or [0.0]
        if time is None:
            chosen = times[-1]
        else:
            chosen = min(times, key=lambda t: (abs(t - time), t))
    else:
        reader = pv.XMLUnstructuredGridReader(FileName=[path])
        chosen = 0.0
    reader.UpdatePipeline(chosen)
    data = reader.GetClientSideObject().GetOutputDataObject(0)
    if data is None or data.GetNumberOfPoints() == 0:
        fail(script, "'%s' has no disks" % path)
    if data.GetPointData().GetArray("radius") is None:
        fail(script, "'%s' has no 'radius' point array (not a hexdem frame?)" % path)
    check_frame_values(script, path, data)
    if not path.lower().endswith(".pvd"):
        time_array = data.GetFieldData().GetArray("time")
        if time_array is not None:
            chosen = time_array.GetValue(0)
    return reader, data, chosen


def make_view(pv, size, time):
    """A white render view at `time` (set before anything is shown, so that the pipelines
    run once, at that time)."""
    view = pv.CreateView("RenderView")
    view.ViewTime = time
    view.ViewSize = list(size)
    view.Background = [1.0, 1.0, 1.0]
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0
    view.OrientationAxesVisibility = 0
    view.CameraParallelProjection = 1
    return view


def frame_box(data, zoom):
    """The box [x0, x1] x [y0, y1] to show: the zoom, or all disks with their radii."""
    if zoom:
        return zoom[0], zoom[1], zoom[2], zoom[3]
    b = data.GetBounds()
    r = data.GetPointData().GetArray("radius").GetRange()[1]
    return b[0] - r, b[2] - r, b[1] + r, b[3] + r


class Camera:
    """Parallel camera that fits a box in the image left of the legend (the right `legend`
    fraction of the image) and under the title."""

    def __init__(self, box, size, legend=0.16):
        x0, y0, x1, y1 = box
        width, height = size
        usable_w, usable_h = (1.0 - legend) * width, height - 50.0
        self.pixels_per_metre = min(usable_w / (x1 - x0), usable_h / (y1 - y0)) / 1.04
        self.half_height = 0.5 * height / self.pixels_per_metre
        self.cx = 0.5 * (x0 + x1) + 0.5 * (width - usable_w) / self.pixels_per_metre
        self.cy = 0.5 * (y0 + y1) + 0.5 * (height - usable_h) / self.pixels_per_metre
        self.depth = 10.0 * max(x1 - x0, y1 - y0)

    def apply(self, pv, view):
        pv.Render(view)  # the first render resets the camera to the data: set ours after it
        view.CameraPosition = [self.cx, self.cy, self.depth]
        view.CameraFocalPoint = [self.cx, self.cy, 0.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.CameraParallelScale = self.half_height


def show_disks(pv, source, view, r_max):
    """Disks at their true size: Point Gaussian splats of radius `radius`."""
    disks = pv.Show(source, view)
    disks.SetRepresentationType("Point Gaussian")
    disks.ShaderPreset = "Plain circle"
    disks.GaussianRadius = 1.0
    disks.ScaleByArray = 1
    disks.SetScaleArray = ["POINTS", "radius"]
    disks.UseScaleFunction = 0
    disks.ScaleTransferFunction.Points = [0.0, 0.0, 0.5, 0.0, r_max, r_max, 0.5, 0.0]
    disks.Emissive = 0
    return disks


def style_scalar_bar(pv, lut, view, title, legend=0.16, categorical=False):
    """The colour legend in the right `legend` fraction of the image; the labels of a
    categorical legend go right of its bar."""
    bar = pv.GetScalarBar(lut, view)
    bar.Title = title
    bar.ComponentTitle = ""
    bar.TitleColor = [0.0, 0.0, 0.0]
    bar.LabelColor = [0.0, 0.0, 0.0]
    bar.TitleFontSize = 16
    bar.LabelFontSize = 14
    bar.WindowLocation = "Any Location"
    if categorical:
        bar.TextPosition = "Ticks left/bottom, annotations right/top"
        bar.Position = [1.0 - legend + 0.02, 0.1]
    else:
        bar.Position = [1.0 - legend + 0.03, 0.1]
    bar.ScalarBarLength = 0.6
    bar.DrawBackground = 1
    bar.BackgroundColor = [1.0, 1.0, 1.0, 1.0]
    bar.BackgroundPadding = 6.0
    return bar


def show_title(pv, view, text):
    title = pv.Text(Text=text)
    display = pv.Show(title, view)
    display.WindowLocation = "Upper Center"
    display.Color = [0.0, 0.0, 0.0]
    display.FontSize = 18
    display.ShowBorder = "Always"
    display.BorderColor = [1.0, 1.0, 1.0]
    display.BackgroundColor = [1.0, 1.0, 1.0, 1.0]


def format_time(t):
    """A time for titles: microseconds or seconds."""
    if t == 0:
        return "t = 0"
    if abs(t) < 1e-2:
        return "t = %.4g us" % (t * 1e6)
    return "t = %.4g s" % t


def save(script, pv, view, path, size):
    pv.SaveScreenshot(path, view, ImageResolution=list(size),
                      OverrideColorPalette="WhiteBackground", TransparentBackground=0)
    if not os.path.isfile(path):
        fail(script, "could not write '%s'" % path)


def finish(script, pv, view, camera, title, path, size):
    """Title, camera, render and PNG: the end of every figure script."""
    show_title(pv, view, title)
    camera.apply(pv, view)
    pv.Render(view)
    save(script, pv, view, path, size)


def field_value(data, name, default=None):
    array = data.GetFieldData().GetAbstractArray(name)
    if array is None or array.GetNumberOfTuples() == 0:
        return default
    return array.GetVariantValue(0).ToDouble()

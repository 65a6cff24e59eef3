"""The `hexdem` Python package: the filters as ordinary VTK classes in a plain VTK pipeline,
in /usr/bin/python3 as in pvpython (PYTHONPATH = the build's site-packages folder).

    PYTHONPATH=<build>/lib/python3.11/site-packages python3 test_python_package.py FRAMES_DIR
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import hexdem  # noqa: E402
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader  # noqa: E402

from frame_checks import (check, close, crack_counts, field, fragment_sizes,  # noqa: E402
                          max_shear, point_array)


def main(frames_dir):
    for name in ("vtkHexDEMMaxShearStress", "vtkHexDEMCrackMap", "vtkHexDEMFragmentCounter"):
        cls = getattr(hexdem, name)
        check(issubclass(cls, vtkAlgorithm), "%s is not a vtkAlgorithm" % name)
        check(cls().GetClassName() == name, "%s: wrong class name" % name)

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(frames_dir, "fractured.vtu"))
    reader.Update()
    frame = reader.GetOutput()

    shear = hexdem.vtkHexDEMMaxShearStress()
    shear.SetInputConnection(reader.GetOutputPort())
    shear.ComputeThreeDimensionalOn()
    shear.Update()
    expected = max_shear(frame)
    check(abs(point_array(shear.GetOutput(), "max_shear") - expected).max() <= 1e-9 * expected.max(),
          "max_shear differs")
    check(shear.GetOutput().GetPointData().GetArray("max_shear_3d_ratio") is not None,
          "no max_shear_3d_ratio")

    cracks = hexdem.vtkHexDEMCrackMap()
    cracks.SetInputConnection(reader.GetOutputPort())
    cracks.SetMergeSegments(False)
    cracks.Update()
    counts, lengths = crack_counts(frame)
    out = cracks.GetOutput()
    check(out.GetNumberOfCells() == sum(counts.values()), "crack segments")
    check(close(field(out, "crack_length"), sum(lengths.values()), 1e-12), "crack_length")

    fragments = hexdem.vtkHexDEMFragmentCounter()
    fragments.SetInputConnection(reader.GetOutputPort())
    fragments.Update()
    sizes = fragment_sizes(frame)
    check(field(fragments.GetOutput(), "fragment_count") == len(sizes), "fragment_count")
    table = fragments.GetTableOutput()
    check([table.GetValueByName(r, "disks").ToInt() for r in range(table.GetNumberOfRows())] == sizes,
          "fragment sizes")
    print("hexdem package test passed (%s)" % sys.executable)


if __name__ == "__main__":
    main(sys.argv[1])

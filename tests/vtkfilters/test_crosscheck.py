"""Cross-check of HexDEM Fragment Counter against ParaView's own filters on a fractured frame
(10 % of the bonds broken at random, two cracks, a crushed zone, contacts):

    Threshold (cell array state between 0 and 1: intact bonds) -> Connectivity

gives one region per fragment with at least one intact bond; the disks with no intact bond
disappear in Threshold and are fragments of one disk each. The fragment count and the
multiset of fragment sizes must agree.

    pvpython test_crosscheck.py FRAMES_DIR PLUGIN.so
"""

import collections
import os
import sys

from paraview import servermanager
from paraview import simple as pv
from vtkmodules.util.numpy_support import vtk_to_numpy


def check(condition, message):
    if not condition:
        raise AssertionError(message)


def main(frames_dir, plugin):
    pv.LoadPlugin(plugin, remote=False)
    reader = pv.XMLUnstructuredGridReader(FileName=[os.path.join(frames_dir, "fractured.vtu")])
    frame = servermanager.Fetch(reader)
    disks = frame.GetNumberOfPoints()
    state = vtk_to_numpy(frame.GetCellData().GetArray("state"))
    broken = ((state >= 2) & (state <= 4)).sum() / float((state <= 4).sum())
    check(0.10 < broken < 0.2, "fractured.vtu: %.1f %% of the bonds broken" % (100 * broken))

    # ParaView's chain.
    threshold = pv.Threshold(Input=reader)
    threshold.Scalars = ["CELLS", "state"]
    threshold.LowerThreshold = 0
    threshold.UpperThreshold = 1
    threshold.ThresholdMethod = "Between"
    connectivity = pv.Connectivity(Input=threshold)
    connectivity.ExtractionMode = "Extract All Regions"
    connectivity.ColorRegions = 1
    regions = servermanager.Fetch(connectivity)
    region_id = vtk_to_numpy(regions.GetPointData().GetArray("RegionId"))
    kept = regions.GetNumberOfPoints()
    isolated = disks - kept
    paraview_sizes = sorted(list(collections.Counter(region_id.tolist()).values()) + [1] * isolated,
                            reverse=True)

    # Ours.
    fragments = pv.HexDEMFragmentCounter(Input=reader)
    out = servermanager.Fetch(fragments)
    table = servermanager.Fetch(fragments, idx=1)
    count = out.GetFieldData().GetArray("fragment_count").GetValue(0)
    our_sizes = [table.GetValueByName(r, "disks").ToInt() for r in range(table.GetNumberOfRows())]

    print("disks %d, bonds broken %.1f %%" % (disks, 100 * broken))
    print("ParaView Threshold + Connectivity: %d regions + %d isolated disks = %d fragments"
          % (len(set(region_id.tolist())), isolated, len(paraview_sizes)))
    print("HexDEM Fragment Counter: %d fragments" % count)
    print("largest fragments: ParaView %s, HexDEM %s" % (paraview_sizes[:6], our_sizes[:6]))
    check(len(paraview_sizes) > 20, "the frame should have many fragments")
    check(count == len(paraview_sizes), "fragment counts differ: %d != %d" % (count, len(paraview_sizes)))
    check(our_sizes == paraview_sizes, "fragment sizes differ")
    check(sum(our_sizes) == disks, "fragments do not cover the disks")
    print("cross-check passed")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])

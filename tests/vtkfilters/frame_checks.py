"""Reference values computed independently of the filters, with numpy and plain Python, from
a hexdem frame (a vtkUnstructuredGrid): used by the ParaView and Python tests."""

import math

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy


def fail(message):
    raise AssertionError(message)


def check(condition, message):
    if not condition:
        fail(message)


def close(a, b, rel=1e-12, abs_=0.0):
    return abs(a - b) <= max(rel * max(abs(a), abs(b)), abs_)


def point_array(grid, name):
    return vtk_to_numpy(grid.GetPointData().GetArray(name))


def cell_array(grid, name):
    return vtk_to_numpy(grid.GetCellData().GetArray(name))


def field(data, name):
    array = data.GetFieldData().GetAbstractArray(name)
    check(array is not None, "no field data '%s'" % name)
    return array.GetVariantValue(0).ToDouble()


def bonds(grid):
    """(i, j) of every line cell."""
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    return conn[0::2], conn[1::2]


def max_shear(grid):
    s = point_array(grid, "stress").reshape(-1, 9)
    return np.sqrt((0.5 * (s[:, 0] - s[:, 4])) ** 2 + (0.5 * (s[:, 1] + s[:, 3])) ** 2)


def crack_counts(grid):
    """Broken bonds per mode {2, 3, 4} and the nominal crack length per mode."""
    state = cell_array(grid, "state")
    radius = point_array(grid, "radius")
    i, j = bonds(grid)
    counts, lengths = {}, {}
    for mode in (2, 3, 4):
        sel = state == mode
        counts[mode] = int(sel.sum())
        lengths[mode] = float((2.0 * 0.5 * (radius[i[sel]] + radius[j[sel]]) / math.sqrt(3.0)).sum())
    return counts, lengths


def fragment_sizes(grid):
    """Sizes of the connected components over intact bonds (state 0, 1), largest first."""
    n = grid.GetNumberOfPoints()
    parent = list(range(n))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    state = cell_array(grid, "state")
    i, j = bonds(grid)
    for a, b in zip(i[state <= 1].tolist(), j[state <= 1].tolist()):
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)
    sizes = {}
    for a in range(n):
        r = find(a)
        sizes[r] = sizes.get(r, 0) + 1
    return sorted(sizes.values(), reverse=True)

#!/usr/bin/env python3
"""Checks that a rendered PNG is a real picture: expected size, and not blank (at least
`min_colours` distinct colours and a fraction of non-background pixels).

    python3 check_png.py IMAGE.png WIDTH HEIGHT [MIN_COLOURS] [MIN_FOREGROUND]
"""
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader


def main():
    path, width, height = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    min_colours = int(sys.argv[4]) if len(sys.argv) > 4 else 3
    min_foreground = float(sys.argv[5]) if len(sys.argv) > 5 else 0.02
    reader = vtkPNGReader()
    if not reader.CanReadFile(path):
        sys.exit(f"{path}: not a PNG file")
    reader.SetFileName(path)
    reader.Update()
    img = reader.GetOutput()
    w, h, _ = img.GetDimensions()
    if (w, h) != (width, height):
        sys.exit(f"{path}: size {w}x{h}, expected {width}x{height}")
    px = vtk_to_numpy(img.GetPointData().GetScalars())[:, :3]
    colours = len(np.unique(px, axis=0))
    background = np.all(px == px[0], axis=1).mean()
    if colours < min_colours or 1 - background < min_foreground:
        sys.exit(f"{path}: looks blank ({colours} colours, {100 * (1 - background):.1f}% foreground)")
    print(f"{path}: {w}x{h}, {colours} colours, {100 * (1 - background):.1f}% foreground")


if __name__ == "__main__":
    main()

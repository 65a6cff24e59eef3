"""hexdem's VTK filters for Python: vtkHexDEMMaxShearStress, vtkHexDEMCrackMap and
vtkHexDEMFragmentCounter, as ordinary VTK classes (see docs/filters.md).

Works in /usr/bin/python3, pvpython and pvbatch with this package's folder on PYTHONPATH.
"""
from .HexDEMFiltersCore import *  # noqa: F401,F403

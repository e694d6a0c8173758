"""Show a DICOM series with depth-enhanced MIP: ``python3 pyvista_dicom_demip.py FOLDER [OUT.png]``.

With OUT.png there is no window: the picture is written there instead.
"""
import sys
import pyvista as pv
import mipcast.filters  # registers plotter.mip
from mipcast.io.dicom import read_dicom

grid = read_dicom(sys.argv[1])  # a folder of slices (or one multi-frame file), in patient mm
plotter = pv.Plotter(off_screen=len(sys.argv) > 2)
plotter.set_background("black")
plotter.mip.add_volume(grid, "demip", cmap="bone", depth_weight=0.3)
plotter.show(screenshot=sys.argv[2] if len(sys.argv) > 2 else None)

"""Compose plugin/representation/distributed-parity.png from representation_distributed_check.py's PNGs.

Usage (after the 1-rank and the 4-rank runs of tests/representation_distributed_check.py with
``--axis 2 --image 128 128 --png-dir DIR``)::

    python3 tests/representation_distributed_figure.py DIR plugin/representation/distributed-parity.png

Panels, left to right: mipcast ``mip`` on 1 rank, on 4 ranks (slabs along z), ParaView's own
MIP on 1 rank, on 4 ranks, and |4 ranks - 1 rank| of ParaView's MIP times 4 (mipcast's
difference is black: at most 1 grey level).
"""
import sys

import numpy as np

from vtk_png import write_png


def load(path):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader

    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    output = reader.GetOutput()
    width, height, _ = output.GetDimensions()
    return vtk_to_numpy(output.GetPointData().GetScalars()).reshape(height, width, -1)[::-1, :, :3].astype(int)


def main(folder, out):
    mip1, mip4 = load(f"{folder}/mip-n1-axis2.png"), load(f"{folder}/mip-n4-axis2.png")
    pv1, pv4 = load(f"{folder}/paraview-mip-n1-axis2.png"), load(f"{folder}/paraview-mip-n4-axis2.png")
    diff = np.clip(np.abs(pv4 - pv1) * 4, 0, 255)
    gap = np.full((mip1.shape[0], 4, 3), 80)
    panels = [mip1, gap, mip4, gap, pv1, gap, pv4, gap, diff]
    write_png(out, np.concatenate(panels, axis=1).astype(np.uint8))


if __name__ == "__main__":
    main(*sys.argv[1:3])

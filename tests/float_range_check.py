"""How far from 1 float values may lie: every method's picture of the vessel phantom (32³, NaN holes, 48²)
times 10^k against the picture of the values themselves, float32 and float64, with mipcast's float limits
switched off (mipcast.core.prepare.FLOAT_LIMITS; docs/reliability.md, "Scalar types").

    python tests/float_range_check.py [SCALE ...]
"""
import sys
import warnings
from unittest import mock

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

import mipcast.filters as filters
from mipcast.core import prepare
from mipcast.data_fixtures import make_fixture

METHODS = ("mip", "analytic", "minip", "analytic_minip", "average", "analytic_average", "demip", "stock",
           "stock_minip", "stock_average")


def main(scales) -> None:
    warnings.simplefilter("ignore")
    image = make_fixture("vessels", size=32)
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape((32, 32, 32)).astype(np.float64)
    values[::7, ::5, ::3] = np.nan
    expected = {m: filters.render(values, m, size=(48, 48)).astype(int) for m in METHODS}
    print("scale dtype " + " ".join(METHODS))
    no_limits = {"float32": (np.inf, 0.0), "float64": (np.inf, 0.0)}
    with mock.patch.dict(prepare.FLOAT_LIMITS, no_limits):
        for scale in scales:
            for dtype in (np.float32, np.float64):
                off = [int(np.abs(filters.render((values * scale).astype(dtype), m, size=(48, 48)) - expected[m]).max())
                       for m in METHODS]
                print(f"{scale:g} {np.dtype(dtype).name} " + " ".join(map(str, off)), flush=True)


if __name__ == "__main__":
    main([float(s) for s in sys.argv[1:]] or [1e-39, 1e-37, 1e-36, 1e-34, 1e-33, 1e20, 1e37, 4e37, 1e38, 1e40])

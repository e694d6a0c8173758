"""A CT-sized synthetic volume: vessels in soft-tissue noise, int16 Hounsfield units."""
from __future__ import annotations

from typing import Sequence

import numpy as np

from mipcast.data_fixtures.synthetic import image_from_array


def ct_volume(shape: Sequence[int] = (400, 512, 512), seed: int = 0):
    """A CT-like int16 volume: soft-tissue noise, contrast-filled vessels and a few calcifications.

    Background: uniform noise in [0, 80) HU (soft tissue); eight straight
    tubes of radius 1.5-3 voxels at 250-600 HU (contrast), Gaussian cross
    section; six calcified spots at 1200-1400 HU.  Spacing 0.7 x 0.7 x 1.0 mm
    (x, y, z) is not used: the spacing is 1, so one sample per voxel is one per millimetre.

    Parameters
    ----------
    shape : (nz, ny, nx)
        Points per axis, array order.
    seed : int
        numpy random seed.

    Returns
    -------
    vtkImageData
        int16 point scalars ``"hu"``.

    Examples
    --------
    >>> image = ct_volume((20, 24, 24))
    >>> image.GetDimensions(), image.GetPointData().GetScalars().GetDataTypeAsString()
    ((24, 24, 20), 'short')
    """
    rng = np.random.default_rng(seed)
    shape = tuple(int(v) for v in shape)
    values = rng.integers(0, 80, size=shape, dtype=np.int16)
    extent = np.array(shape, float) - 1.0
    for _ in range(8):
        start, end = rng.uniform(0.1, 0.9, 3) * extent, rng.uniform(0.1, 0.9, 3) * extent
        end[rng.integers(3)] = extent[rng.integers(3)] * rng.choice([0.02, 0.98])
        _stamp_tube(values, start, end, rng.uniform(1.5, 3.0), rng.uniform(250, 600))
    for _ in range(6):
        centre = rng.uniform(0.15, 0.85, 3) * extent
        _stamp_tube(values, centre, centre + 1.0, rng.uniform(1.0, 2.0), rng.uniform(1200, 1400))
    return image_from_array(values, name="hu")


def _stamp_tube(values: np.ndarray, start: np.ndarray, end: np.ndarray, radius: float, peak: float) -> None:
    """Raise ``values`` to a Gaussian tube from ``start`` to ``end`` (array-order coordinates)."""
    reach = int(np.ceil(2.5 * radius))
    offsets = np.stack(np.meshgrid(*[np.arange(-reach, reach + 1)] * 3, indexing="ij"), -1).reshape(-1, 3)
    steps = max(2, int(np.linalg.norm(end - start) * 2))
    direction = (end - start) / max(np.linalg.norm(end - start), 1e-9)
    for point in np.linspace(start, end, steps):
        cells = np.round(point).astype(int) + offsets
        keep = np.all((cells >= 0) & (cells < values.shape), axis=1)
        cells = cells[keep]
        along = (cells - point) @ direction
        distance2 = np.sum((cells - point) ** 2, axis=1) - along ** 2
        tube = (peak * np.exp(-distance2 / (2 * radius ** 2))).astype(np.int16)
        index = tuple(cells.T)
        values[index] = np.maximum(values[index], tube)




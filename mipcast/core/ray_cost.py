"""Rays cast and samples taken by one grid of rays: the cost columns of Levoy & Whitaker's Table I.

Counted on the CPU from the same geometry the GPU uses: one ray per texel
centre of the grid (VTK's ``ImageSampleDistance`` grid spans the viewport),
through the camera's composite projection at the viewport's aspect, the
volume's matrix and the image's index mapping.  A ray is *cast* when its
texel is not skipped and it meets the volume's point-bounds box (only then
does the rasterised box produce a fragment).  *Samples* are what the ray
loop reads: ``max(1, floor(L / d))`` for a sampled loop with step ``d`` over
the length ``L`` inside the box (``shaders/sampled_loop.glsl``), or the
cells a cell-walking loop visits (analytic MIP, ``shaders/amip_loop.glsl``).
"""
from __future__ import annotations

from typing import Optional, Sequence, Tuple

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.camera_rays import box_interval, index_space, matrix_array, pixel_centres, unproject


def grid_cost(image: vtkImageData, camera, size: Sequence[int], grid: Sequence[int], *,
              volume_matrix=None, cast: Optional[np.ndarray] = None,
              sample_distance: Optional[float] = None,
              cells_of: Optional[vtkImageData] = None) -> Tuple[int, int]:
    """(rays cast, samples taken) by one grid of rays over the viewport.

    Parameters
    ----------
    image : vtkImageData
        The full-resolution volume (its box is what rays meet).
    camera : vtkCamera
        The view.
    size : (width, height)
        The viewport in pixels (sets the projection's aspect).
    grid : (columns, rows)
        Rays across and up; texel centres at ``(i + 0.5) / columns``.
    volume_matrix : vtkMatrix4x4, optional
        The vtkVolume's model-to-world matrix (identity if omitted).
    cast : numpy.ndarray of bool, shape (rows, columns), optional
        Texels whose ray is cast (top row first); all if omitted.
    sample_distance : float, optional
        Step of a sampled loop, model units.  Give this or ``cells_of``.
    cells_of : vtkImageData, optional
        Count the cells of this image (a pyramid level with the same bounds)
        that a cell-walking loop visits.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> image = vtkImageData()
    >>> image.SetDimensions(5, 5, 5)
    >>> camera = vtkCamera()
    >>> camera.SetPosition(2.0, 2.0, 20.0)
    >>> camera.SetFocalPoint(2.0, 2.0, 2.0)
    >>> camera.SetParallelProjection(True)
    >>> camera.SetParallelScale(2.0)
    >>> grid_cost(image, camera, (4, 4), (4, 4), sample_distance=1.0)
    (16, 64)
    >>> grid_cost(image, camera, (4, 4), (4, 4), cells_of=image)
    (16, 64)
    """
    if (sample_distance is None) == (cells_of is None):
        raise ValueError("give exactly one of sample_distance and cells_of")
    width, height = (max(int(v), 1) for v in size)
    columns, rows = (int(v) for v in grid)
    if columns < 1 or rows < 1:
        return 0, 0
    world_to_ndc = matrix_array(camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1))
    model_to_world = np.eye(4) if volume_matrix is None else matrix_array(volume_matrix)
    ndc_to_model = np.linalg.inv(world_to_ndc @ model_to_world)
    x, y = pixel_centres(columns, rows)
    keep = np.ones((rows, columns), bool) if cast is None else np.asarray(cast, bool)
    ys, xs = np.nonzero(keep)
    if xs.size == 0:
        return 0, 0
    model = unproject(ndc_to_model, x[xs], y[ys])
    to_index, upper = index_space(image)
    index = model @ to_index[:3, :3].T + to_index[:3, 3]
    start, delta = index[0], index[1] - index[0]
    t_near, t_far = box_interval(start, delta, upper)  # t = 0 on the near plane, 1 on the far plane
    t_near, t_far = np.maximum(t_near, 0.0), np.minimum(t_far, 1.0)
    hit = t_near <= t_far
    rays = int(np.count_nonzero(hit))
    if rays == 0:
        return 0, 0
    t_near, t_far = t_near[hit], t_far[hit]
    if sample_distance is not None:
        length = (t_far - t_near) * np.linalg.norm(model[1, hit] - model[0, hit], axis=1)
        samples = np.maximum(1, np.floor(length / float(sample_distance) + 1e-9))
        return rays, int(samples.sum())
    scale = (np.array(cells_of.GetDimensions(), float) - 1.0) / np.maximum(upper, 1e-30)
    entry = (start[hit] + t_near[:, None] * delta[hit]) * scale
    leave = (start[hit] + t_far[:, None] * delta[hit]) * scale
    top = np.array(cells_of.GetDimensions(), float) - 2.0
    crossings = np.abs(np.clip(np.floor(leave), 0, top) - np.clip(np.floor(entry), 0, top)).sum(axis=1)
    return rays, int((crossings + 1).sum())

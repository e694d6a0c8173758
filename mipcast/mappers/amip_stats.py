"""Work analytic MIP does per ray: cells walked, cubics solved, blocks jumped, texel fetches.

The counters live in the shader (``shaders/amip_cell.glsl``) and are read
back through the float readout path, one counter per render, with the
display's shortcuts (transfer-function floor and ceiling) on, as when the
picture is drawn.  Cells crossed
come from the CPU ray geometry (:func:`mipcast.core.camera_rays.camera_rays`), so
the share of cells the walk skipped is measured, not estimated.
"""
from __future__ import annotations

import numpy as np

from mipcast.core.camera_rays import camera_rays
from mipcast.mappers.float_readout import read_normalised
from mipcast.core.object_state import object_state

_COUNTERS = ("cells_walked", "cells_solved", "blocks_jumped")


def work_per_ray(scene) -> dict:
    """Mean work per hit ray of an analytic-MIP :class:`~mipcast.offscreen.OffscreenView`.

    Returns
    -------
    dict
        ``cells_crossed`` (cells the ray passes through, counted from the
        voxel planes between entry and exit on the CPU; rays that touch an
        edge or face count a cell more than the walk visits), ``cells_walked``
        (visited by the walk), ``cells_solved`` (cubic evaluated),
        ``blocks_jumped``, ``texel_fetches`` (per walked cell 2 from the
        packed corners, 8 without packing; plus one block-maximum fetch
        per step when blocks are used),
        ``skipped_cells`` (share of crossed cells never fetched) and
        ``skipped_cubics`` (share of walked cells whose cubic was skipped).

    Examples
    --------
    >>> from mipcast.offscreen import OffscreenView
    >>> from mipcast.data_fixtures import make_fixture
    >>> scene = OffscreenView(make_fixture("vessels", size=24), "analytic", size=(32, 32), window="full")
    >>> work = work_per_ray(scene)
    >>> round(work["cells_crossed"]), round(work["cells_walked"]), work["blocks_jumped"]
    (24, 23, 0.0)
    """
    mapper, state = scene.mapper, object_state(scene.mapper)
    counts = {}
    try:
        for index, name in enumerate(_COUNTERS):
            state["stat"] = index
            # the shader writes -1e-4 * count as the normalised value (amip_stats_readout.glsl)
            counts[name] = np.round(-read_normalised(scene.render_window, mapper) / 1.0e-4)
    finally:
        state.pop("stat", None)
    hits = ~np.isnan(counts["cells_walked"])
    crossed = _cells_crossed(scene)
    blocks = "amip_loop_blocks" in mapper.GetShaderPieces()
    walked, solved, jumped = (counts[n][hits] for n in _COUNTERS)
    per_cell = 2 if "amip_corners_packed" in mapper.GetShaderPieces() else 8
    fetches = per_cell * walked + (walked + jumped if blocks else 0)
    return {"cells_crossed": float(crossed[hits].mean()), "cells_walked": float(walked.mean()),
            "cells_solved": float(solved.mean()), "blocks_jumped": float(jumped.mean()),
            "texel_fetches": float(fetches.mean()),
            "skipped_cells": float(1.0 - walked.sum() / max(crossed[hits].sum(), 1.0)),
            "skipped_cubics": float(1.0 - solved.sum() / max(walked.sum(), 1.0))}


def _cells_crossed(scene) -> np.ndarray:
    rays = camera_rays(scene.image, scene.camera, scene.size)
    entry = rays.origin + rays.direction * rays.t_enter[..., None]
    exit_ = rays.origin + rays.direction * rays.t_exit[..., None]
    planes = np.abs(np.floor(exit_) - np.floor(entry)).sum(axis=-1)
    return np.where(rays.hit, planes + 1.0, np.nan)

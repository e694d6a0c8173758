"""Content-adaptive ray density in a foveated frame: where each finer level casts its rays.

:mod:`mipcast.core.content_adaptive` defines the test (float64, numpy); this
module runs it in a frame.  After a deciding level is drawn, its picture is
tested at its texels, on the GPU (:func:`refinement_test` runs
``shaders/foveated_refine_pass.glsl`` on copies of the picture from before
and after the frame's levels, :func:`coarse_textures`; the finer levels read
the result and the fovea's spans, :func:`fovea_texture`) or, on the CPU
path, from the picture read back (:func:`read_texels`), the masks uploaded
as textures (:func:`mask_texture`).  The data's bound on where a
full-quality ray may meet structure (:func:`above_floor_boxes`,
:func:`structure_texels`, :mod:`mipcast.core.structure_bound`) joins the
fovea's structure test; :func:`outline_cover` and :func:`draw_cover` put the
picture beneath back over the deciding levels' stretch past the volume's
outline.  :func:`gpu_masks` reads a GPU frame's masks back for the cost
accounting.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Optional, Union

import numpy as np
from vtkmodules.vtkCommonCore import VTK_UNSIGNED_CHAR

from mipcast.core import content_adaptive, foveation, structure_bound
from mipcast.core.prepare import prepare_scalars
from mipcast.core.transfer_bounds import constant_ends
from mipcast.mappers import refine_pass
from mipcast.mappers.max_blocks import block_maxima
from mipcast.mappers.private_draw import copy_drawn, draw_over, kept_texture, read_rgba, texture_target

if TYPE_CHECKING:
    from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject


def gpu_masks_possible(state, renderer) -> bool:
    """Whether the refinement masks can be built on the GPU (else the CPU path reads the picture back).

    Not with a VTK that cannot say which framebuffer is being drawn, and
    not when ``object_state(mapper)["masks_on_cpu"]`` asks for the CPU
    reference path.
    """
    if state.get("masks_on_cpu"):
        return False
    return hasattr(renderer.GetRenderWindow().GetState(), "GetCurrentDrawFramebufferState")


def coarse_textures(state, renderer, viewport) -> dict:
    """The two viewport-sized RGBA8 textures a deciding level's picture is copied into (after, before the frame)."""
    window = renderer.GetRenderWindow()
    entry = state.get("coarse_textures")
    size = (viewport[2], viewport[3])
    if entry is None or entry["window"] is not window or entry["size"] != size:
        entry = {"window": window, "size": size, "framebuffers": {}}
        for name in ("after", "before"):
            entry[name], entry["framebuffers"][name] = texture_target(window, *size)
        state["coarse_textures"] = entry
    return entry


def fovea_texture(state, renderer, plan, layer) -> vtkTextureObject:
    """A level's fovea spans (:func:`mipcast.core.content_adaptive.fovea_spans`) as a float texture, one texel a row.

    Made again only when the grid, gaze, aspect or fovea change: it does not depend on the picture.
    """
    from vtkmodules.vtkCommonCore import VTK_FLOAT
    from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject

    window = renderer.GetRenderWindow()
    radius = content_adaptive.fovea_radius(plan, layer)
    key = (window.GetAddressAsString("vtkObjectBase"), tuple(layer.grid), tuple(plan.gaze), plan.aspect, radius)
    cache = state.setdefault("fovea_textures", {})
    cached = cache.get(layer.level)
    if cached is not None and cached[0] == key and cached[1].GetContext() is window:
        return cached[1]
    texture = cached[1] if cached is not None and cached[1].GetContext() is window else vtkTextureObject()
    texture.SetContext(window)
    texture.SetMinificationFilter(vtkTextureObject.Nearest)
    texture.SetMagnificationFilter(vtkTextureObject.Nearest)
    spans = np.ascontiguousarray(content_adaptive.fovea_spans(layer.grid, plan, radius), dtype=np.float32)
    texture.Create2DFromRaw(spans.shape[0], 1, 2, VTK_FLOAT, spans)
    texture.Deactivate()
    cache[layer.level] = (key, texture)
    return texture


def download_texels(window, texture, grid) -> np.ndarray:
    """A coarse-picture texture (RGB, uint8) at the texel centres of ``grid``, top row first.

    A readback: only :meth:`FoveatedVolumeMapper.GetLastFrameCost` calls it, after the frame.
    """
    return content_adaptive.coarse_texels(download_picture(window, texture), grid)


def download_picture(window, texture) -> np.ndarray:
    """An RGBA8 picture texture's RGB (uint8), top row first (a readback)."""
    window.MakeCurrent()
    width, height = texture.GetWidth(), texture.GetHeight()
    data = np.zeros((height, width, 4), np.uint8)
    texture.Download().Download2D(VTK_UNSIGNED_CHAR, data, [width, height], 4, [0, 0])
    return data[::-1, :, :3]


def outline_cover(renderer, plan, silhouette, coarse, before) -> Optional[tuple]:
    """(box, RGBA8 patch): the picture from before the frame's first level over the deciding levels' stretch past
    the volume's outline, with level 0's weight (:func:`mipcast.core.content_adaptive.outline_cover`), or None
    (and no readback) where the outline does not reach level 0's disc.  ``coarse``: the GPU path's copies (that
    picture read back from them), else ``before``, the picture the CPU path read."""
    cover = content_adaptive.outline_cover(plan, silhouette)
    if cover is None:
        return None
    (x0, y0, columns, rows), weight = cover
    picture = download_picture(renderer.GetRenderWindow(), coarse["before"]) if coarse is not None else before
    height = picture.shape[0]
    beneath = picture[height - y0 - rows:height - y0, x0:x0 + columns]
    return (x0, y0, columns, rows), content_adaptive.cover_patch(weight, beneath.astype(np.float64)).astype(np.uint8)


def draw_cover(renderer, state, viewport, box, patch) -> None:
    """Draw an :func:`outline_cover` patch over its box of the viewport, premultiplied "over"."""
    x0, y0, columns, rows = box
    _, _, width, height = viewport
    window = renderer.GetRenderWindow()
    texture = kept_texture(state, "outline_texture", window)
    texture.Create2DFromRaw(columns, rows, 4, VTK_UNSIGNED_CHAR, np.ascontiguousarray(patch[::-1]))
    left, right = 2.0 * x0 / width - 1.0, 2.0 * (x0 + columns) / width - 1.0
    bottom, top = 2.0 * y0 / height - 1.0, 2.0 * (y0 + rows) / height - 1.0
    draw_over(window, texture, viewport, [([0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0],
                                           [left, bottom, 0.0, right, bottom, 0.0, right, top, 0.0, left, top, 0.0])])


def gpu_masks(frame) -> dict:
    """The refinement masks of a frame whose masks the GPU built: its refine passes' tests read back."""
    coarse, plan = frame["coarse"], frame["plan"]
    tests = {}
    for source, texture in coarse["tests"].items():
        test = download_texels(coarse["window"], texture, plan.layers[source].grid)
        tests[source] = test[..., 0] > 127, test[..., 1] > 127
    return {layer.level: content_adaptive.refinement_mask(*tests[content_adaptive.decided_by(plan, index)], plan, layer)
            for index, layer in enumerate(plan.layers) if index >= 1}


def refinement_test(state, renderer, volume, viewport, plan, source, tolerance, values, coarse,
                    before) -> Union[tuple, vtkTextureObject]:
    """The refinement test of the picture the layers up to ``source`` left, at that layer's texels.

    ``values``: the levels' float readouts and the rays their masks left out
    (a readout: their composite, over black); else ``coarse``: the GPU's copies (after, before), the refine
    pass's texture returned; else the picture read back, ``before`` the
    viewport's before the frame's first level.
    """
    grid = plan.layers[source].grid
    if values is not None:
        so_far = foveation.composite_values(plan._replace(layers=plan.layers[:source + 1]), *values)
        after = grey_texels(volume, content_adaptive.coarse_texels(so_far, grid))
        return content_adaptive.refinement_test(after, np.zeros_like(after), tolerance)
    if coarse is not None:
        copy_drawn(renderer, viewport, coarse["framebuffers"]["after"])
        whole_fovea = content_adaptive.casts_whole_fovea(plan, plan.layers[source + 1])
        return refine_pass.run_refine_pass(state, renderer.GetRenderWindow(), coarse, viewport, grid, tolerance,
                                           whole_fovea=whole_fovea)
    after = read_texels(renderer, viewport, grid)
    return content_adaptive.refinement_test(after, content_adaptive.coarse_texels(before, grid), tolerance)


def read_texels(renderer, viewport, grid) -> np.ndarray:
    """The window's picture (RGB, uint8) at the texel centres of ``grid``, top row first."""
    picture = read_rgba(renderer.GetRenderWindow(), viewport)[::-1, :, :3]  # (the levels after it keep their boxes)
    return content_adaptive.coarse_texels(picture, grid)


def grey_texels(volume, values) -> np.ndarray:
    """Grey levels (over black) the volume's transfer functions give a level's float readout."""
    prop = volume.GetProperty()
    colour, opacity = prop.GetRGBTransferFunction(0), prop.GetScalarOpacity(0)
    finite = np.nan_to_num(values, nan=-np.inf)
    low, high = colour.GetRange()
    points = np.linspace(low, high, 1024)
    table = np.array([colour.GetColor(v)[0] * opacity.GetValue(v) for v in points])
    grey = np.interp(np.clip(finite, low, high), points, table) * 255.0
    return np.where(np.isfinite(finite), np.round(grey), 0.0)[..., None]


def structure_texels(state, plan, source, image, volume, camera, viewport, boxes) -> np.ndarray:
    """Texels of ``plan.layers[source]`` near the fovea whose cell a full-quality ray above the floor may cross.

    :func:`mipcast.core.structure_bound.splat_texels` of ``boxes``, the
    blocks of ``image`` above the transfer functions' floor
    (:func:`above_floor_boxes`; an MPI rank: its piece's); the texels that matter
    are those a fovea ray's nearest texel can be (eccentricity below the
    plan's ``start`` plus half a texel's diagonal).  The boxes' projections
    (:func:`~mipcast.core.structure_bound.texel_ranges`) are kept in
    ``state`` while the view and the boxes stand still, and from the
    second frame of a still view the splat of every box too: a moving gaze
    then only masks it (at 1024², content-adaptive, wall ms a frame of this
    function, the gaze moving: vessels 128³ 2.0 -> 0.9, head CT 2.8 -> 1.0;
    a turning camera splats only the boxes near the fovea, as before).
    """
    grid = plan.layers[source].grid
    columns, rows = grid
    reach = 0.5 * math.hypot(plan.aspect / columns, 1.0 / rows)
    near_fovea = foveation.eccentricity(grid, plan.gaze, plan.aspect) < plan.start + reach
    to_ndc = structure_bound.ndc_from_index(image, camera, viewport[2] / viewport[3], volume.GetMatrix())
    view = (to_ndc.tobytes(), tuple(grid))
    kept = state.get("bound_splat")
    if kept is None or kept[0] is not boxes or kept[1] != view:  # a new view: the boxes near the fovea alone
        kept = state["bound_splat"] = [boxes, view, structure_bound.texel_ranges(boxes, to_ndc, grid), None]
        return structure_bound.splat_ranges(kept[2], grid, near_fovea)
    if kept[3] is None:  # the view stands still: every box, once; a moving gaze then only masks it
        kept[3] = structure_bound.splat_ranges(kept[2], grid, np.ones((rows, columns), bool))
    return kept[3] & near_fovea


def above_floor_boxes(state, image, volume, values=None, data_range=None, dims=None) -> np.ndarray:
    """The boxes of ``image``'s drawn values above the transfer functions' floor, in its index space.

    :func:`mipcast.core.structure_bound.blocks_above`; blocks of one cell
    (volumes up to :data:`~mipcast.core.structure_bound.FLAG_CELLS` + 1
    points along every axis) shrunk to their half cells above the floor
    (:func:`~mipcast.core.structure_bound.halved_cells`).  The block maxima
    are kept per input, the boxes per floor.  ``values`` (z, y, x; NaN:
    missing), ``data_range`` and ``dims`` (the whole volume's, for the
    block size) for an MPI rank's piece; by default the input's prepared
    values, range and dimensions.  Cell scalars (values one point fewer per
    axis: drawn on the cell centres, VTK filling the outer half cell with
    the edge values) give whole blocks grown by half a cell on every side:
    ``[lower, upper + 1]``.
    """
    component = state["preparer"].GetComponent() if "preparer" in state else -1
    dims = tuple(dims or image.GetDimensions())
    block = structure_bound.block_size(dims)
    stamp = (image.GetAddressAsString("vtkObjectBase"), image.GetMTime(), component, data_range, dims)
    cached = state.get("block_maxima")
    if cached is None or cached[0] != stamp:
        if values is None:
            prepared = prepare_scalars(image, component)
            values, data_range = prepared.values, (prepared.low, prepared.high)
        values = np.asarray(values)
        if np.issubdtype(values.dtype, np.floating) and np.isnan(values).any():  # missing: below every value
            values = np.where(np.isnan(values), -np.inf, values)
        drawn = values.shape[::-1]
        cells = tuple(drawn) != tuple(image.GetDimensions())
        halving = values if block == 1 and not cells else None   # (a large volume's values are not kept)
        cached = state["block_maxima"] = (stamp, block_maxima(values, block), data_range, drawn, cells, halving, {})
    _, maxima, (low, high), drawn, cells, halving, found = cached
    floor = constant_ends(volume.GetProperty(), low, high)[0]
    if floor not in found:
        found.clear()  # one transfer function at a time
        boxes = structure_bound.blocks_above(maxima, floor, block, drawn)
        if cells:  # cell scalars: centre i at index i + 1/2, and half a cell more each side
            boxes[:, 1] += 1.0
        elif halving is not None:
            boxes = structure_bound.halved_cells(halving, boxes, floor)
        found[floor] = boxes
    return found[floor]


def bound_texture(state, renderer, grid, bound: Optional[np.ndarray]) -> vtkTextureObject:
    """The structure bound as a 2D texture of ``grid`` (:func:`mask_texture`; zeros for None)."""
    return mask_texture(state, renderer, "bound", np.zeros(tuple(grid)[::-1], bool) if bound is None else bound)


def beneath_texture(state, renderer, before: np.ndarray) -> vtkTextureObject:
    """The viewport's picture before the frame's first level (RGB, top row first) as an RGBA8 texture."""
    height, width = before.shape[:2]
    texture = kept_texture(state, "beneath_texture", renderer.GetRenderWindow())
    data = np.empty((height, width, 4), np.uint8)
    data[..., :3], data[..., 3] = before[::-1], 255
    texture.Create2DFromRaw(width, height, 4, VTK_UNSIGNED_CHAR, np.ascontiguousarray(data))
    return texture


def mask_texture(state, renderer, level, mask) -> vtkTextureObject:
    """A bool grid (a level's refinement mask, the structure bound) as a nearest-filtered 2D texture (bottom row
    first), kept per ``level`` key."""
    textures = state.setdefault("mask_textures", {})
    window = renderer.GetRenderWindow()
    texture = kept_texture(textures, level, window)
    data = np.ascontiguousarray(mask[::-1], dtype=np.uint8) * np.uint8(255)
    rows, columns = data.shape
    texture.Create2DFromRaw(columns, rows, 1, VTK_UNSIGNED_CHAR, data)
    return texture

"""DEMIP and the averages composited exactly over the ranks of one parallel render view.

ParaView's render view on N ranks (``mpiexec -n N pvbatch``, ``pvserver``)
draws each rank's piece and composites the ranks' images with IceT.  The
maximum and minimum projections composite exactly by depth
(plugin/representation/mipcast_representation.py, ``depth_composite_op``);
DEMIP and the averages need more than one value per pixel.  Here each rank
renders its piece's phase(s) privately into float readouts, exactly as
:mod:`mipcast.mappers.bricked_demip` and :mod:`mipcast.mappers.bricked_draw`
render a brick, and the readouts are reduced over the ranks by a ``reduce``
callable (the representation passes ParaView's
``vtkMultiProcessController.AllReduce``), so every rank ends with the SAME
final picture:

- rule ``"demip"`` (``demip``, ``demip_two_pass``): MAX of the pieces'
  sampled MIP (the whole ray's maximum), then MIN of the whole-ray index of
  each piece's first sample of that GLOBAL maximum's material
  (:class:`mipcast.mappers.demip_brick.DEMIPBrickDepthMapper`), then depth,
  Eq. 1 and the colour sphere on the CPU
  (:func:`mipcast.mappers.demip_composite.demip_composite`); DEMIP's ordered
  projections (LMIP, attenuated MIP, MIDA) go rank after rank, front to
  back (:mod:`mipcast.mappers.rank_ordered`, which needs ``rank``);
- rule ``"mean"`` (``average``, ``analytic_average``, and VTK's own
  ``stock_average``, its pieces read out by ``average``'s mapper: VTK's
  samples and weights): SUM over ranks of the pieces' counted samples / ray
  length and of their weighted means, divided by the total, coloured through
  the volume property as the single volume colours its mean; for VTK's own
  average the sums of opacity and opacity x value, its grey.

Every rank enters every reduction of its rule, also a rank whose piece is
out of view, empty or failed to render (it contributes nothing: -inf, +inf
or 0), so the sequence of collectives is the same on all ranks.  The shape
and the scalar range are reduced first; a rank that finds them inconsistent
gives up together with all the others (no picture, no hang).

Examples
--------
>>> import numpy as np
>>> from mipcast.mappers.rank_composite import combine_mean
>>> total, weighted, plain, hits = (np.array([3.0, 0.0]), np.array([6.0, 0.0]),
...                                 np.array([0.0, 0.0]), np.array([2.0, 0.0]))
>>> combine_mean(total, weighted, plain, hits).tolist()
[2.0, nan]
"""
from __future__ import annotations

from typing import Callable, Optional, Tuple

import numpy as np

from mipcast.core.object_state import object_state
from mipcast.core.parameter_tables import DEMIP_SETTINGS
from mipcast.mappers import bricked_draw, float_readout
from mipcast.mappers.private_draw import draw_over, kept_texture
from mipcast.mappers.brick_rays import box_in_view, brick_entry, push_whole_rays, whole_geometry
from mipcast.mappers.stereo import draw_for

#: Reduce(array, op) -> the array reduced over every rank; op is "max", "min" or "sum".
Reduce = Callable[[np.ndarray, str], np.ndarray]

#: Why a piece of VTK's own mapper holding missing values is not read out: VTK's ray caster has no missing test and
#: leaves them to the GPU's NaN arithmetic; fill them first as the whole volume (the representation does:
#: InputPreparer.SetWholeRange, then the filled piece is passed here).
OWN_MISSING = ("VTK's own ray caster leaves missing (NaN/Inf) values to the GPU's NaN arithmetic: pass its piece "
               "filled relative to the whole volume's finite range (InputPreparer.SetWholeRange)")
#: Stand-ins for "nothing on this rank" in the reductions (float64 carries them exactly).
_LOW, _HIGH = -1.0e300, 1.0e300
_GL_DEPTH_BUFFER_BIT, _GL_SCISSOR_TEST = 0x00000100, 0x0C11


def single(array: np.ndarray, op: str) -> np.ndarray:
    """The reduction of one process: the array itself (for tests and one rank).

    >>> single(np.array([1.0]), "max").tolist()
    [1.0]
    """
    return np.asarray(array, dtype=np.float64)


def combine_mean(total: np.ndarray, weighted: np.ndarray, plain: np.ndarray, hits: np.ndarray) -> np.ndarray:
    """The mean over ranks: sum(weight x mean) / sum(weight); where no rank counted weight but some had
    a value (a ray grazing an edge), the plain mean of those values (as bricked_draw's weighted mean)."""
    mean = np.where(total > 0.0, weighted / np.where(total > 0.0, total, 1.0),
                    plain / np.where(hits > 0.0, hits, 1.0))
    return np.where(hits > 0.0, mean, np.nan)


def piece_range(piece) -> Tuple[float, float, bool]:
    """(low, high, missing): the finite range of ``piece``'s scalars and whether it holds missing (NaN/Inf) values.

    Kept per array and modification time (every frame asks).  An empty piece, or one holding only missing
    values: ``(+big, -big, missing)``, nothing to the range reductions.

    >>> import numpy as np
    >>> from vtkmodules.util.numpy_support import numpy_to_vtk
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> piece = vtkImageData()
    >>> piece.SetDimensions(2, 1, 1)
    >>> _ = piece.GetPointData().SetScalars(numpy_to_vtk(np.array([2.0, np.nan]), deep=True))
    >>> piece_range(piece)
    (2.0, 2.0, True)
    """
    scalars = piece.GetPointData().GetScalars() if piece is not None and piece.GetNumberOfPoints() else None
    if scalars is None:
        return _HIGH, _LOW, False
    state = object_state(scalars)
    cached = state.get("piece_range")
    if cached is not None and cached[0] == scalars.GetMTime():
        return cached[1]
    from vtkmodules.util.numpy_support import vtk_to_numpy

    values = vtk_to_numpy(scalars)
    finite = np.isfinite(values) if values.dtype.kind == "f" else np.ones(values.shape, dtype=bool)
    found = (float(values[finite].min()), float(values[finite].max())) if finite.any() else (_HIGH, _LOW)
    result = found + (not finite.all(),)
    state["piece_range"] = (scalars.GetMTime(), result)
    return result


def _entries(mapper, piece, whole, rule: str, kind) -> list:
    """This rank's private brick entries of its piece, drawn by ``kind`` (cached on ``mapper``'s state)."""
    from mipcast.mappers.demip_brick import DEMIPBrickDepthMapper
    from mipcast.mappers.mip import MIPVolumeMapper

    state = object_state(mapper)
    extent = tuple(piece.GetExtent())
    key = (piece.GetAddressAsString("vtkObjectBase"), piece.GetMTime(), extent, tuple(whole), rule, kind)
    cached = state.get("rank_bricks")
    if cached is not None and cached[0] == key:
        return cached[1]
    from mipcast.mappers.bricks import extract_brick

    dims = piece.GetDimensions()
    # as bricked_draw's bricks: an image of its own whose extent starts at 0, placed where the piece is
    piece = extract_brick(piece, (0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1))
    distance = mapper.GetSampleDistance()
    if rule == "demip":
        entries = [brick_entry(phase, piece, extent, whole, piece.GetSpacing(), distance)
                   for phase in (MIPVolumeMapper, DEMIPBrickDepthMapper)]
    else:
        entry = brick_entry(kind, piece, extent, whole, piece.GetSpacing(), distance)
        object_state(entry["mapper"])["global_cells"] = False  # cells lie whole in a piece
        object_state(entry["mapper"])["brick_mean"] = True
        entry["volume"].GetShaderProperty().GetFragmentCustomUniforms().SetUniformf("u_mc_brickChannel", 0.0)
        entries = [entry]
    state["rank_bricks"] = (key, entries)
    return entries


def _render(renderer, entry, whole_image, camera, shape, channel: Optional[float] = None,
            raw: bool = False) -> np.ndarray:
    """One float readout of this rank's brick (data units, or ``raw`` as written), NaN: none."""
    brick_mapper, brick_volume = entry["mapper"], entry["volume"]
    draw_for(brick_mapper, camera, renderer)
    push_whole_rays(entry["volume"], entry["mapper"].GetSampleDistance(), whole_image, camera, (shape[1], shape[0]))
    object_state(brick_mapper)["exact_readout"] = True
    brick_mapper.RenderToImageOn()
    brick_mapper.SetDepthImageScalarTypeToFloat()
    uniforms = brick_volume.GetShaderProperty().GetFragmentCustomUniforms()
    try:
        if channel is not None:
            uniforms.SetUniformf("u_mc_brickChannel", float(channel))
        brick_volume.RenderVolumetricGeometry(renderer)
        return bricked_draw.brick_readout(brick_mapper, shape, raw=raw)
    finally:
        object_state(brick_mapper).pop("exact_readout", None)
        brick_mapper.RenderToImageOff()
        if channel is not None:
            uniforms.SetUniformf("u_mc_brickChannel", 0.0)


def _global_scalars(scalars, low: float, high: float):
    """An array of ``scalars``' type holding the whole volume's range (VTK's normalisation of the whole)."""
    whole = scalars.NewInstance()
    whole.SetNumberOfComponents(1)
    whole.InsertNextTuple1(low)
    whole.InsertNextTuple1(high)
    return whole


def compose(mapper, volume, renderer, piece, whole_stub, reduce: Reduce,
            rule: str, rank: Tuple[int, int] = (0, 1), brick=None) -> Tuple[Optional[np.ndarray], Optional[str]]:
    """This frame's final premultiplied RGBA (top row first), the same on every rank; or (None, why).

    Parameters
    ----------
    mapper, volume : the representation's mipcast mapper and its vtkVolume (this rank's piece).
    renderer : vtkRenderer
        The view's renderer (camera, viewport size), inside its render.
    piece : vtkImageData or None
        This rank's piece (the mapper's input); None or empty: it takes part with nothing.
    whole_stub : (whole extent, origin, spacing, direction 3x3 row-major)
    reduce : :data:`Reduce`
    rule : ``"demip"`` or ``"mean"``
    rank : (this rank's index, the number of ranks)
        For DEMIP's ordered projections (:mod:`mipcast.mappers.rank_ordered`: each rank's row of the pieces).
    brick : class, optional
        The mipcast mapper class that reads the piece out (default: ``mapper``'s own class); for VTK's own
        mapper (``stock_average``) the method that reproduces its samples (the method table's ``readout_by``:
        :class:`~mipcast.mappers.projections.AverageVolumeMapper`).

    Every rank must call this the same number of times per frame; it enters
    the same reductions whatever happens locally.
    """
    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    shape = (max(height[0], 1), max(width[0], 1))
    scalars = None
    usable = piece is not None and piece.GetNumberOfPoints() > 0
    if usable:
        scalars = piece.GetPointData().GetScalars()
        usable = scalars is not None
    low, high, missing = piece_range(piece if usable else None)
    camera = renderer.GetActiveCamera()
    kind = brick if brick is not None else type(mapper)
    # the whole volume in the world, as the representation's volume's matrix places it (its display transform)
    whole_image = (whole_geometry(whole_stub, volume.GetMatrix() if volume is not None else None)
                   if whole_stub is not None else None)
    # 1: shape, finite range, missing values (every rank); a mismatch: all give up alike
    head = reduce(np.array([shape[0], shape[1], -shape[0], -shape[1], -low, high, float(missing)],
                           dtype=np.float64), "max")
    if head[0] != -head[2] or head[1] != -head[3]:
        return None, f"the ranks' viewports differ ({int(head[0])}x{int(head[1])} vs {int(-head[2])}x{int(-head[3])})"
    low, high, missing = float(-head[4]), float(head[5]), bool(head[6] > 0.0)
    if not high >= low:
        return None, "no rank has data"
    if missing and brick is not None:
        return None, OWN_MISSING
    entries, local_problem = [], None
    usable = usable and mapper is not None and whole_image is not None
    if usable:
        try:
            entries = _entries(mapper, piece, whole_stub[0], rule, kind)
            for entry in entries:
                bricked_draw.follow_brick(mapper, volume, entry) if rule == "mean" else _follow_demip(
                    mapper, volume, entry, entry is entries[1])
                # after following (which gives a brick the user's mapper's fill range, here this piece's own):
                # missing values filled as in the whole volume (none: the piece as it is)
                entry["mapper"].GetInputPreparer().SetWholeRange((low, high) if missing else None)
            if not box_in_view(entries[0]["volume"], renderer, shape):
                entries = []
        except Exception as error:  # noqa: BLE001  (reported; the collectives still run)
            entries, local_problem = [], repr(error)
    whole_scalars = _global_scalars(scalars, low, high) if scalars is not None else None
    if entries:
        _clear_depth(renderer)
    if rule == "demip":
        from mipcast.mappers import rank_ordered  # every projection: "mip" by _demip, the others turn by turn

        rgba, problem = rank_ordered.demip(mapper, volume, renderer, entries, whole_image, camera, shape, reduce,
                                           (low, high), local_problem, rank, missing)
    else:
        rgba, problem = _mean(mapper, volume, renderer, entries, whole_image, camera, shape, reduce, whole_scalars,
                              (low, high), local_problem, stock=brick is not None)
    return rgba, problem


def _clear_depth(renderer) -> None:
    """Clear the bound framebuffer's depth over the renderer's viewport: VTK's ray caster ends rays at the
    depth it finds there, and before the frame (the renderer's StartEvent) that is the last frame's (the
    renderer clears it next).  The scissor box is set to the viewport: the one VTK left may be another
    (a fresh window's first frame: a clear cut short, phase 1's MIP 0.13 low on 91 % of the rays)."""
    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    gl = renderer.GetRenderWindow().GetState()
    gl.Push()
    try:
        gl.vtkglDepthMask(True)
        gl.vtkglEnable(_GL_SCISSOR_TEST)
        gl.vtkglScissor(x0[0], y0[0], max(width[0], 1), max(height[0], 1))
        gl.vtkglClearDepth(1.0)
        gl.vtkglClear(_GL_DEPTH_BUFFER_BIT)
    finally:
        gl.Pop()


def _follow_demip(mapper, volume, entry, demip: bool) -> None:
    from mipcast.mappers import bricked_demip

    bricked_demip.follow_demip_brick(mapper, volume, entry, mapper.GetSampleDistance(), demip=demip)


def _demip(mapper, volume, renderer, entries, whole_image, camera, shape, reduce, data_range, problem):
    from mipcast.mappers.demip_brick import bind_maximum, match_index
    from mipcast.mappers.demip_composite import demip_composite, demip_premultiplied

    values = np.full(shape, np.nan)
    if entries:
        try:  # phase 1: this piece's sampled MIP of the whole volume's samples
            found = _render(renderer, entries[0], whole_image, camera, shape)
            values = found.astype(np.float32).astype(np.float64)
        except Exception as error:  # noqa: BLE001
            problem, entries = repr(error), []
    flag = np.array([1.0 if problem else 0.0])
    reduced = reduce(np.concatenate([np.where(np.isnan(values), _LOW, values).ravel(), flag]), "max")
    failed = reduced[-1] > 0.0
    values = reduced[:-1].reshape(shape)
    values = np.where(values <= 0.5 * _LOW, np.nan, values)
    index = np.full(shape, np.inf)
    if entries and not failed:
        try:  # phase 2: the first sample of the GLOBAL maximum's material on this piece
            bind_maximum(renderer.GetRenderWindow(), entries[1]["mapper"], values, data_range)
            index = match_index(_render(renderer, entries[1], whole_image, camera, shape, raw=True))  # 1 - index, not data units
        except Exception as error:  # noqa: BLE001
            problem = repr(error)
    flag = np.array([1.0 if problem else 0.0])
    reduced = reduce(np.concatenate([np.where(np.isfinite(index), index, _HIGH).ravel(), -flag]), "min")
    failed = failed or reduced[-1] < 0.0
    if failed:
        return None, problem or "a rank failed to render its piece"
    if mapper is None or whole_image is None:
        return None, None  # a rank without data: it took part, it draws nothing
    index = reduced[:-1].reshape(shape)
    index = np.where(index >= 0.5 * _HIGH, np.inf, index)
    params = {p.name: getattr(mapper, p.getter)() for p in DEMIP_SETTINGS}
    from mipcast.mappers.clip_uniforms import slab_of

    depth, rgb = demip_composite(whole_image, camera, mapper.GetSampleDistance(), values, index, params,
                                 volume.GetProperty(), slab=slab_of(mapper, camera))
    return demip_premultiplied(values, rgb, volume.GetProperty()), None


def _mean(mapper, volume, renderer, entries, whole_image, camera, shape, reduce, whole_scalars, data_range,
          problem, stock):
    """The average over the ranks: ``stock`` (VTK's own, read out by ``average``'s pieces) its grey of the
    opacity-weighted mean normalised over the whole range; mipcast's averages their mean coloured through the
    volume property (``shaders/average_color.glsl``)."""
    size = shape[0] * shape[1]
    local = np.zeros((4, size))
    if entries:
        entry = entries[0]
        try:
            piece_scalars = entry["mapper"].GetRenderedInput().GetPointData().GetScalars()
            if stock:  # count n, mean opacity, mean opacity x s (s: this piece's normalised scalar)
                n, mean_opacity, mean_shade = (_render(renderer, entry, whole_image, camera, shape, channel=c,
                                                       raw=True) for c in (1, 2, 3))
                n = np.nan_to_num(-n)
                plow, phigh = piece_scalars.GetRange(0)
                scale = float_readout.texture_scale(piece_scalars)
                o = n * np.nan_to_num(mean_opacity)
                q = n * np.nan_to_num(mean_shade)
                local[0] = n.ravel()
                local[1] = o.ravel()
                local[2] = ((plow * o + (phigh - plow) * q) / scale).ravel()  # sum of opacity x value
            else:  # the mean (data units) and the samples / ray length it counted
                mean = _render(renderer, entry, whole_image, camera, shape, channel=0)
                weight = np.nan_to_num(-_render(renderer, entry, whole_image, camera, shape, channel=1, raw=True))
                hit = np.isfinite(mean)
                weight = np.where(hit, weight, 0.0)
                local[0] = weight.ravel()
                local[1] = np.where(weight > 0.0, np.nan_to_num(mean) * weight, 0.0).ravel()
                local[2] = np.where(hit, np.nan_to_num(mean), 0.0).ravel()
                local[3] = hit.ravel()
        except Exception as error:  # noqa: BLE001
            problem, local[:] = repr(error), 0.0
    flag = np.array([1.0 if problem else 0.0])
    reduced = reduce(np.concatenate([local.ravel(), flag]), "sum")
    if reduced[-1] > 0.0:
        return None, problem or "a rank failed to render its piece"
    if mapper is None:
        return None, None  # a rank without data: it took part, it draws nothing
    total = reduced[:-1].reshape(4, shape[0], shape[1])
    if not stock:
        return bricked_draw.colour(combine_mean(total[0], total[1], total[2], total[3]), volume.GetProperty()), None
    g0, g1 = _shade_map(whole_scalars, volume, data_range)
    count, opacity, weighted = total[0], total[1], total[2]
    grey = np.where(count > 0.0, (g0 * opacity + g1 * weighted) / np.where(count > 0.0, count, 1.0), np.nan)
    hit = np.isfinite(grey)
    rgba = np.zeros(shape + (4,), dtype=np.float32)
    rgba[hit, :3] = np.clip(grey[hit], 0.0, 1.0)[:, None]
    rgba[hit, 3] = 1.0
    return rgba, None


def _shade_map(whole_scalars, volume, data_range) -> tuple:
    """(g0, g1): the whole volume's grey of value v is g0 + g1 v (VTK's normalisation of the WHOLE range)."""
    if whole_scalars is None:  # this rank has no data: the same numbers from the range alone
        low, high = data_range
        span = high - low if high > low else 1.0
        return -low / span, 1.0 / span
    g0 = float(float_readout.from_data_units(np.array([0.0]), whole_scalars)[0])
    g1 = float(float_readout.from_data_units(np.array([1.0]), whole_scalars)[0]) - g0
    return g0, g1


def projection(renderer) -> np.ndarray:
    """The renderer's camera projection (4x4, as VTK draws with it now, the tiled aspect ratio)."""
    matrix = renderer.GetActiveCamera().GetProjectionTransformMatrix(renderer.GetTiledAspectRatio(), -1.0, 1.0)
    return np.array([[matrix.GetElement(r, c) for c in range(4)] for r in range(4)])


def ndc_transform(start: np.ndarray, now: np.ndarray) -> Tuple[float, float, float, float]:
    """(sx, tx, sy, ty) with NDC_now = s NDC_start + t, from two projections of one camera.

    IceT draws each rank with the camera's projection pre-multiplied by a 2D
    scale and shift (the part of the tile the rank's geometry covers, at the
    origin of its buffer); the picture made at the renderer's StartEvent is
    drawn through the same shift.  Rows x and y only (the clipping range may
    change the others).

    >>> p = np.array([[2.0, 0, 0.1, 0], [0, 2.0, 0, 0], [0, 0, -1.0, -0.2], [0, 0, -1.0, 0]])
    >>> icet = np.array([[1, 0, 0, 0.25], [0, 1, 0, -0.5], [0, 0, 1, 0], [0, 0, 0, 1.0]]) @ p
    >>> [round(v, 6) for v in ndc_transform(p, icet)]
    [1.0, 0.25, 1.0, -0.5]
    """
    result = []
    for row in (0, 1):
        basis = np.stack([start[row], start[3]], axis=1)
        (scale, shift), *_ = np.linalg.lstsq(basis, now[row], rcond=None)
        result += [float(scale), float(shift)]
    return tuple(result)


def draw(state, renderer, rgba: np.ndarray, ndc=(1.0, 0.0, 1.0, 0.0)) -> None:
    """Draw the final picture over the renderer's viewport, premultiplied, writing depth 0.5.

    Every rank draws the same picture, so whichever fragment IceT's Z-buffer
    compositing keeps is right.  ``ndc``: :func:`ndc_transform` from the
    projection the picture was made with to the one drawn with now.  The quad
    (VTK's texture copy, at window depth 0.5) is limited to the rows and
    columns that hold a value.
    """
    from vtkmodules.vtkCommonCore import VTK_FLOAT

    hit = rgba[..., 3] > 0.0
    if not hit.any():
        return
    rows, cols = np.nonzero(hit.any(axis=1))[0], np.nonzero(hit.any(axis=0))[0]
    top, bottom, left, right = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
    part = rgba[top:bottom, left:right]
    window = renderer.GetRenderWindow()
    texture = kept_texture(state, "rank_texture", window)
    height, width = part.shape[:2]
    data = np.ascontiguousarray(part[::-1], dtype=np.float32)  # bottom row first
    state["rank_rows"] = data
    texture.Create2DFromRaw(width, height, 4, VTK_FLOAT, data)
    full_w, full_h, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(full_w, full_h, x0, y0)
    sx, tx, sy, ty = ndc
    W, H = full_w[0], full_h[0]

    def pixel(p, size, scale, shift):  # a pixel edge of the full picture -> of the drawn buffer
        return ((2.0 * p / size - 1.0) * scale + shift + 1.0) * 0.5 * size

    xa, xb = pixel(left, W, sx, tx), pixel(right, W, sx, tx)
    ya, yb = pixel(H - bottom, H, sy, ty), pixel(H - top, H, sy, ty)
    x, y = x0[0] + int(round(xa)), y0[0] + int(round(ya))
    w, h = max(int(round(xb - xa)), 1), max(int(round(yb - ya)), 1)
    draw_over(window, texture, (x, y, w, h), depth=True)

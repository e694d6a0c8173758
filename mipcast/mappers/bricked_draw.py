"""A mipcast mapper drawing a volume beyond the 3D texture limit in bricks, inside the user's render.

When a mapper's input has more points along an axis than the GPU's 3D
texture limit (:func:`texture_limit`), one texture cannot hold it.  Methods
whose composite over disjoint parts of a ray is exact (the mapper class's
``BRICKS``: ``"max"`` for MIP and analytic MIP, ``"min"`` for MinIP and
analytic MinIP, ``"mean"`` for the averages) then draw it in bricks inside the same ``Render()``:

1. the volume is split into bricks of at most ``limit`` points per axis that
   share one layer of points (:func:`mipcast.mappers.bricks.brick_extents`),
   every cell lying whole in one brick;
2. each brick is drawn by a private mapper of the same class (the user's
   parameters, sample distance, cropping, clipping, matrix and property:
   :func:`mipcast.mappers.private_draw.follow_volume`) with the renderer's
   camera into a float readout (data units); sampled bricks take the whole
   volume's sample positions (the ``global_phase`` piece, as
   :mod:`mipcast.distributed` does), cell-walking bricks need nothing more;
3. the readouts are combined by ``fmax`` / ``fmin`` (exact: the maximum over
   disjoint sample or cell sets is the maximum over their union), coloured
   through the volume property (colour x opacity, premultiplied, as
   ``shaders/mip_color.glsl``), and the picture is drawn into the window's
   current framebuffer over the renderer's viewport with premultiplied
   blending, where the mapper's own draw would have gone (its own draw is
   skipped, so no texture beyond the limit is ever uploaded).

During a float readout (:func:`mipcast.mappers.float_readout.render_float`)
the combined values are what the mapper's ``GetDepthImage`` returns, so
readouts, :class:`mipcast.offscreen.OffscreenView`, the pyvista filters and
the ParaView representation all see the bricked volume as one.

The averages (``BRICKS`` ``"mean"``) combine the bricks' means weighted by
what each brick counted: the number of the whole ray's samples (sampled
average) or the length of the ray (analytic average), written by a further
pass of the brick (its class's ``BRICK_READOUT`` piece, channel
``u_mc_brickChannel``), so clipping, cropping and missing values are the
GPU's; the combined mean is coloured as the maxima are.  DEMIP (``BRICKS = "demip"``) is drawn in two phases by
:mod:`mipcast.mappers.bricked_demip`; foveated (``BRICKS = "foveated"``) composites
each level too large for one texture over its bricks before blending it
(:mod:`mipcast.mappers.bricked_foveated`, :func:`compose` on the level's ray
grid).  Methods whose composite is none of these (a new sampled projection)
refuse such a volume with a message naming the limit and the fix
(:func:`refusal`).  The whole box's outline rays whose one (clamped) sample
lies in a brick they do not cross get it on the CPU
(:mod:`mipcast.mappers.outline_rays`, MAX and MIN).  Cost: one render per brick in view per frame plus one
readback each (docs/reliability.md, "GPU limits and memory"); bricks whose box
lies outside the view are skipped.

Examples
--------
>>> from mipcast.mappers.mip import MIPVolumeMapper
>>> mapper = MIPVolumeMapper()
>>> bricking_limit(mapper)   # no input, no window: nothing to brick
0
"""
from __future__ import annotations

from typing import Optional

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_FLOAT
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.object_state import object_state
from mipcast.mappers import clip_uniforms, float_readout, outline_rays
from mipcast.mappers.brick_rays import (box_in_view, brick_entry, cached_bricks, nearest_interpolation, placed,
                                       push_rays)
from mipcast.mappers.box_outline import box_corners, front_faces
from mipcast.mappers.input_preparer import piece_range
from mipcast.mappers.private_draw import (auto_sample_distance, draw_over, follow_volume, kept_texture,
                                          rendering_renderer)
from mipcast.mappers.stereo import draw_for


def _weighted_mean(values: list, weights: list) -> np.ndarray:
    """The bricks' means weighted by what each counted (NaN where none had a value).

    Where every brick's weight is 0 but some had a value (a ray grazing an
    edge: its entry value), the mean of those values.

    Examples
    --------
    >>> nan = np.nan
    >>> _weighted_mean([np.array([1.0, nan, 2.0]), np.array([4.0, nan, nan])],
    ...                [np.array([1.0, 0.0, 0.0]), np.array([2.0, 0.0, 0.0])]).tolist()
    [3.0, nan, 2.0]
    """
    stack = np.array(values, dtype=np.float64)
    weight = np.where(np.isfinite(stack), np.array(weights, dtype=np.float64), 0.0)
    total = weight.sum(axis=0)
    weighted = np.where(weight > 0.0, np.nan_to_num(stack) * weight, 0.0).sum(axis=0)
    hit = np.isfinite(stack).any(axis=0)
    plain = np.nanmean(np.where(hit[None], stack, 0.0), axis=0)
    mean = np.where(total > 0.0, weighted / np.where(total > 0.0, total, 1.0), plain)
    return np.where(hit, mean, np.nan)


#: How the bricks' values combine, per ``BRICKS`` value of a mapper class: ``"mean"`` (average,
#: analytic average) weights each brick's mean by the samples / ray length it counted, read from
#: the GPU by further passes of the brick (its ``BRICK_READOUT`` piece, ``u_mc_brickChannel``).
COMPOSITES = {"max": np.fmax, "min": np.fmin, "mean": _weighted_mean}

#: Normalised readout values beyond this are a brick's empty ray (no sample, no cell): no value.
_EMPTY = 1.0e3

#: Samples of the transfer functions for colouring on the CPU (linear between them).
_TABLE = 8192


def texture_limit(mapper) -> int:
    """``GL_MAX_3D_TEXTURE_SIZE`` of the window drawing ``mapper``'s volume (0 while unknown).

    Asked once per mapper (cached in its state as ``texture_limit``, which
    tests may set to pretend a smaller GPU) through
    :func:`mipcast.mappers.gpu_limits.max_texture_size_3d`, once the window
    has a context (an answer below 2, e.g. VTK's -1 outside the current
    context, is not kept: 0, unknown).
    """
    from mipcast.mappers import gpu_limits

    state = object_state(mapper)
    if "texture_limit" not in state:
        volume = mapper.GetAttachedVolume()
        for index in range(volume.GetNumberOfConsumers() if volume is not None else 0):
            window = getattr(volume.GetConsumer(index), "GetRenderWindow", lambda: None)()
            if window is not None and window.GetNeverRendered() == 0:
                limit = gpu_limits.max_texture_size_3d(window)
                if limit >= 2:  # -1 (VTK) when asked outside the window's current context: ask again later
                    state["texture_limit"] = limit
                break
    return state.get("texture_limit", 0)


def exceeds_limit(mapper) -> int:
    """The texture limit when ``mapper``'s input exceeds it along some axis, else 0."""
    limit = texture_limit(mapper)
    if limit < 2:
        return 0
    preparer = mapper.GetInputPreparer()  # not mapper.GetInput(): this is asked while the input is routed
    image = preparer.GetInputDataObject(0, 0) if preparer.GetNumberOfInputConnections(0) else None
    if image is None or not image.IsA("vtkImageData") or image.GetNumberOfPoints() == 0:
        return 0
    return limit if max(image.GetDimensions()) > limit else 0


def bricking_limit(mapper) -> int:
    """The limit ``mapper`` draws its input in bricks of, or 0 (one texture, or a method that cannot).

    Examples
    --------
    >>> from mipcast.mappers.projections import AverageVolumeMapper
    >>> bricking_limit(AverageVolumeMapper())
    0
    """
    if getattr(type(mapper), "BRICKS", None) not in COMPOSITES and not _demip(mapper):
        return 0
    return exceeds_limit(mapper)


def _demip(mapper) -> bool:
    """DEMIP: drawn in bricks by :mod:`mipcast.mappers.bricked_demip` (two phases, not one composite)."""
    return getattr(type(mapper), "BRICKS", None) == "demip"


def refusal(mapper) -> Optional[str]:
    """The message refusing an input beyond the texture limit for a method that cannot brick it, or None.

    Examples
    --------
    >>> from mipcast.mappers.demip import DEMIPVolumeMapper
    >>> refusal(DEMIPVolumeMapper()) is None   # no input yet
    True
    """
    if getattr(type(mapper), "BRICKS", None) in COMPOSITES:
        return None
    if getattr(type(mapper), "BRICKS", None) == "foveated":  # its levels brick themselves, by their layer
        from mipcast.mappers import bricked_foveated

        return bricked_foveated.refusal(mapper, mapper.GetMethod())
    limit = exceeds_limit(mapper)
    if not limit:
        return None
    if _demip(mapper):
        from mipcast.mappers import bricked_demip

        return bricked_demip.problem(mapper, limit)
    dims = mapper.GetInputPreparer().GetInputDataObject(0, 0).GetDimensions()
    return (f"the volume's dimensions {dims} exceed this GPU's 3D texture limit of {limit} points per "
            f"axis, and {type(mapper).__name__} cannot draw it in bricks exactly (its ray value over "
            "several bricks is not their maximum, minimum or weighted mean): resample the volume to at most "
            f"{limit} points per axis (e.g. vtkImageResample), crop it (vtkExtractVOI), or use a method "
            "that draws it in bricks (mip, analytic, minip, analytic_minip, average, analytic_average)")


# -- the observers (module functions: no reference cycles) --------------------------
def draw_bricks(mapper, event) -> None:
    """VolumeMapperRenderStartEvent: draw the bricks and skip the mapper's own draw (if bricked)."""
    state = object_state(mapper)
    if state.get("render_problem") is not None:
        return
    limit = bricking_limit(mapper)
    if not limit:
        if "bricks" in state:
            _release(state)
        return
    volume = mapper.GetAttachedVolume()
    renderer = rendering_renderer(mapper, volume)
    state["brick_own_draw"] = (mapper.GetCropping(), mapper.GetCroppingRegionPlanes())
    try:
        if renderer is not None:
            with outline_rays.depth_held(renderer):  # one depth readback for the whole bricked frame
                gl = renderer.GetRenderWindow().GetState()
                gl.Push()  # the bricks' render-to-image passes set their own viewport and framebuffer
                try:
                    if _demip(mapper):
                        from mipcast.mappers import bricked_demip

                        values, depth, rgba = bricked_demip.compose(mapper, volume, renderer, limit)
                        if mapper.GetReadout() == "depth":  # the readout's encoding of the depth
                            values = float_readout.to_data_units(depth, mapper.GetRenderedInput().GetPointData()
                                                                 .GetScalars())
                    else:
                        values, rgba = compose(mapper, volume, renderer, limit), None
                finally:
                    gl.Pop()
                if state.get("exact_readout"):
                    state["brick_readout"] = values
                else:
                    _draw_picture(mapper, renderer, volume, values, rgba)
    except Exception as error:  # noqa: BLE001  (an observer: reported as mipcast's refusals are)
        from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow

        problem = f"drawing the volume in bricks of {limit} points per axis failed: {error!r}"
        state["render_problem"] = problem
        vtkOutputWindow.GetInstance().DisplayErrorText(f"{type(mapper).__name__}: {problem}\n")
        mapper.InvokeEvent(vtkCommand.ErrorEvent)
    # never the own draw (the volume is beyond one texture): invalid cropping planes make VTK
    # skip the render silently (no texture upload)
    mapper.SetCropping(True)
    mapper.SetCroppingRegionPlanes(1.0, 0.0, 1.0, 0.0, 1.0, 0.0)


def restore_own_draw(mapper, event) -> None:
    """VolumeMapperRenderEndEvent: the user's cropping back after a bricked frame."""
    saved = object_state(mapper).pop("brick_own_draw", None)
    if saved is not None:
        mapper.SetCropping(saved[0])
        mapper.SetCroppingRegionPlanes(*saved[1])


def fill_depth_image(mapper, image) -> bool:
    """During a bricked float readout, put the combined values into ``image``; False otherwise."""
    values = object_state(mapper).pop("brick_readout", None)
    if values is None:
        return False
    height, width = values.shape
    scalars = mapper.GetRenderedInput().GetPointData().GetScalars()
    raw = float_readout.encode(float_readout.from_data_units(values, scalars))
    image.SetDimensions(width, height, 1)
    array = numpy_to_vtk(np.ascontiguousarray(raw[::-1], dtype=np.float32).ravel(), deep=True)
    image.GetPointData().SetScalars(array)
    return True


# -- the bricks -------------------------------------------------------------------
def bricks_of(mapper, limit: int) -> list:
    """The private (mapper, volume, matrix) of each brick, made when the input or the limit changed."""
    def make(piece, extent, whole):
        entry = brick_entry(type(mapper), piece, extent, whole, piece.GetSpacing(), mapper.GetSampleDistance())
        brick_state = object_state(entry["mapper"])
        # cells lie whole in a brick: the plain walk is exact, and it ends at opaque geometry
        brick_state["global_cells"] = False
        brick_state["brick_mean"] = type(mapper).BRICKS == "mean"  # its BRICK_READOUT piece
        entry["volume"].GetShaderProperty().GetFragmentCustomUniforms().SetUniformf("u_mc_brickChannel", 0.0)
        return entry
    return cached_bricks(mapper, limit, "bricks", make)


def _release(state) -> None:
    state.pop("bricks", None)


def follow_brick(mapper, volume, entry, image_sample_distance: float = 1.0) -> None:
    """The brick's mapper and volume as the user's: parameters, sampling, cropping, clipping, matrix.

    ``image_sample_distance``: the brick's rays (1: one per pixel; a foveated level's coarser grid).
    """
    brick_mapper, brick_volume = entry["mapper"], entry["volume"]
    for parameter in getattr(type(mapper), "PARAMETERS", ()):  # none on VTK's own (stock_average's pieces)
        value = getattr(mapper, parameter.getter)()
        if getattr(brick_mapper, parameter.getter)() != value:
            getattr(brick_mapper, parameter.setter)(value)
    if hasattr(mapper, "GetComponent") and brick_mapper.GetComponent() != mapper.GetComponent():
        brick_mapper.SetComponent(mapper.GetComponent())
    if hasattr(mapper, "GetInputPreparer"):  # missing values filled as in the whole volume, not the brick's range
        brick_mapper.GetInputPreparer().SetWholeRange(piece_range(mapper.GetInputPreparer()))
    if brick_mapper.GetAverageIPScalarRange() != mapper.GetAverageIPScalarRange():  # the averages' counted values
        brick_mapper.SetAverageIPScalarRange(mapper.GetAverageIPScalarRange())
    brick_mapper.SetAutoAdjustSampleDistances(False)
    distance = mapper.GetSampleDistance()
    if mapper.GetAutoAdjustSampleDistances():  # VTK's automatic distance without time-based reduction
        distance = auto_sample_distance(mapper.GetInput(), volume)
    if brick_mapper.GetSampleDistance() != distance:
        brick_mapper.SetSampleDistance(distance)
    if brick_mapper.GetImageSampleDistance() != image_sample_distance:
        brick_mapper.SetImageSampleDistance(image_sample_distance)  # the readouts are combined ray by ray
    follow_volume(mapper, volume, brick_mapper, brick_volume, entry["matrix"])
    clip_uniforms.copy_clipping(mapper, brick_mapper)


def compose(mapper, volume, renderer, limit: int, image_sample_distance: float = 1.0, grid=None) -> np.ndarray:
    """Render every brick's float readout with ``renderer``'s camera and combine them.

    ``image_sample_distance`` and ``grid`` (columns, rows): rays on a coarser
    grid than the viewport's pixels (VTK's reduced framebuffer of that image
    sample distance; a foveated level, :mod:`mipcast.mappers.bricked_foveated`);
    the result then has ``grid``'s shape.

    Bricks combined by their mean (``BRICKS`` "mean") render two passes,
    channels of their ``BRICK_READOUT`` piece: the mean and its weight.

    Returns
    -------
    numpy.ndarray, shape (height, width) of the renderer's viewport, float64
        Data units, NaN where no brick's ray had a value.  Top row first.
    """
    rule = type(mapper).BRICKS
    combine = COMPOSITES[rule]
    channels = (0, 1) if rule == "mean" else (0,)
    passes = []
    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    shape = (max(height[0], 1), max(width[0], 1))
    aspect_size = (shape[1], shape[0])
    if grid is not None:
        shape = (int(grid[1]), int(grid[0]))
    result = np.full(shape, np.nan)
    empty = np.zeros(shape, dtype=bool)
    drawn_any = np.zeros(shape, dtype=bool)  # a brick drew a fragment
    camera = renderer.GetActiveCamera()
    drawn = 0
    step, sampled = None, False
    for entry in bricks_of(mapper, limit):
        brick_mapper, brick_volume = entry["mapper"], entry["volume"]
        follow_brick(mapper, volume, entry, image_sample_distance)
        if not box_in_view(brick_volume, renderer, shape):
            continue  # its box covers no pixel: nothing to draw, nothing to combine
        drawn += 1
        step = brick_mapper.GetSampleDistance()
        draw_for(brick_mapper, camera, renderer)
        push_rays(mapper, entry, camera, shape, aspect_size)
        sampled = "global_phase" in brick_mapper.GetShaderPieces()
        object_state(brick_mapper)["exact_readout"] = True
        brick_mapper.RenderToImageOn()
        brick_mapper.SetDepthImageScalarTypeToFloat()
        uniforms = brick_volume.GetShaderProperty().GetFragmentCustomUniforms()
        read = []
        try:
            for channel in channels:
                if rule == "mean":
                    uniforms.SetUniformf("u_mc_brickChannel", float(channel))
                brick_volume.RenderVolumetricGeometry(renderer)
                if rule == "mean":
                    read.append(brick_readout(brick_mapper, shape, raw=channel > 0))
                else:  # and the rays it drew without a sample (mipcast.mappers.outline_rays)
                    texels = brick_texels(brick_mapper, shape)
                    empty |= np.abs(texels) > _EMPTY  # MIP's -1e30, MinIP's +1e30 (decoded as no fragment)
                    drawn_any |= texels != 1.0
                    read.append(_data_units(brick_mapper, np.where(np.abs(texels) > _EMPTY, np.nan,
                                                                   float_readout.decode(texels))))
        finally:
            object_state(brick_mapper).pop("exact_readout", None)
            brick_mapper.RenderToImageOff()
            if rule == "mean":
                uniforms.SetUniformf("u_mc_brickChannel", 0.0)
        if rule == "mean":
            passes.append((read, brick_mapper.GetRenderedInput().GetPointData().GetScalars()))
        else:
            result = combine(result, read[0])
    object_state(mapper)["bricks_drawn"] = drawn
    object_state(mapper)["brick_sampling"] = (step, sampled)  # for the rays off the box (_face_values)
    image = placed(mapper.GetRenderedInput(), volume.GetMatrix())  # the CPU's rays: the volume's matrix folded in
    if rule != "mean":
        undrawn = outline_rays.undrawn(mapper, renderer, drawn_any)
        if sampled:
            result = outline_rays.complete(result, empty, image, camera, aspect_size, step, combine, undrawn=undrawn,
                                           nearest=nearest_interpolation(volume))
        elif undrawn is not None and (undrawn & np.isnan(result)).any():  # a walk's rays have no clamped sample;
            # those the whole box's raster covers on its outline and no brick's does: walked on the CPU
            from mipcast import reference

            kernel = getattr(reference.mip, _WALKS[rule])
            result = combine(result, outline_rays.walked(image, camera, shape, aspect_size,
                                                         undrawn & np.isnan(result), kernel, step))
        return seen(mapper, result)  # the CPU's rays that saw no finite data: background, as the bricks' own
    if not passes:
        return result
    counts = [read[1] for read, _ in passes]  # -n: the samples (ray length) each counted
    mean = combine([read[0] for read, _ in passes], [np.nan_to_num(-n) for n in counts])
    if sampled:  # a grazing ray whose one sample no brick drawing it holds: on the CPU, clipped as the loop clips
        none = np.sum([np.nan_to_num(-n) for n in counts], axis=0) == 0.0  # (a brick's ray without one: discarded)
        none &= outline_rays.unhidden(renderer, image, shape, aspect_size, step, none)  # not behind opaque geometry
        sample = outline_rays.single_samples(image, camera, shape, aspect_size, step, none,
                                             outline_rays.cut_by(mapper, camera, image),
                                             nearest=nearest_interpolation(volume))
        low, high = _counted_range(mapper)
        mean = np.where(np.isfinite(sample) & (sample >= low) & (sample <= high), sample, mean)
    return mean


def _prepared(mapper):
    """What ``mapper``'s preparer made of the whole volume (:class:`mipcast.core.prepare.PreparedScalars`)."""
    mapper.GetRenderedInput()  # brought up to date
    return mapper.GetInputPreparer().GetPrepared()


def seen(mapper, values: np.ndarray) -> np.ndarray:
    """``values`` (data units) with the rays that saw no finite data NaN (missing values: the whole volume's
    thresholds, :meth:`mipcast.core.prepare.PreparedScalars.seen`; the rays computed on the CPU need it)."""
    prepared = _prepared(mapper)
    return values if prepared is None else prepared.seen(values)


def _counted_range(mapper) -> tuple:
    """The values a sampled average counts: its ``AverageIPScalarRange``, from the finite floor up with
    missing values (the fill does not count: ``u_mc_averageLow``, :class:`mipcast.mappers.projections.AverageVolumeMapper`)."""
    low, high = mapper.GetAverageIPScalarRange()
    prepared = _prepared(mapper)
    return (low if prepared is None else max(low, prepared.missing_below)), high


def _sample_mean(mapper, samples: np.ndarray) -> np.ndarray:
    """The sampled average of a ray's samples (..., k) (NaN: none) in data units: the plain mean of those in
    ``AverageIPScalarRange`` (from the finite floor up: :func:`_counted_range`; ``shaders/average_hooks.glsl``);
    NaN where none counts."""
    low, high = _counted_range(mapper)
    counted = (samples >= low) & (samples <= high)
    total = np.sum(np.where(counted, samples, 0.0), axis=-1)
    n = counted.sum(axis=-1)
    return np.where(n > 0, total / np.maximum(n, 1), np.nan)


def brick_texels(brick_mapper, shape) -> np.ndarray:
    """One brick's readout as its readout piece wrote it (top row first; 1: no fragment, see
    :func:`mipcast.mappers.float_readout.decode`)."""
    image = vtkImageData()
    brick_mapper.GetDepthImage(image)
    scalars = image.GetPointData().GetScalars()
    if scalars is None:
        return np.ones(shape)
    columns, rows, _ = image.GetDimensions()
    if (rows, columns) != tuple(shape):
        raise RuntimeError(f"a brick's readout is {(rows, columns)}, the viewport {tuple(shape)}")
    return vtk_to_numpy(scalars).reshape(rows, columns)[::-1].astype(np.float64)


def brick_readout(brick_mapper, shape, raw: bool = False) -> np.ndarray:
    """One brick's readout in data units (top row first), NaN where its ray had no value.

    ``raw``: the decoded value as the readout piece wrote it (a weight channel), not mapped.
    """
    normalised = float_readout.decode(brick_texels(brick_mapper, shape))
    if raw:
        return normalised
    return _data_units(brick_mapper, np.where(np.abs(normalised) > _EMPTY, np.nan, normalised))


def _data_units(brick_mapper, normalised: np.ndarray) -> np.ndarray:
    """A brick's normalised readout in data units."""
    return float_readout.to_data_units(normalised, brick_mapper.GetRenderedInput().GetPointData().GetScalars())


# -- the picture ----------------------------------------------------------------
def colour(values: np.ndarray, volume_property) -> np.ndarray:
    """Data values -> premultiplied RGBA float32 (colour x opacity, alpha = opacity); NaN: transparent.

    The volume property's colour and scalar-opacity transfer functions of
    component 0, tabulated at 8192 points over the values' range, within
    the functions' own range where both clamp (VTK's default: beyond their
    points they hold their end values), and interpolated linearly (what
    ``shaders/mip_color.glsl`` writes). Until 2026-12-05 the table spanned the
    values' whole range: a value far outside the functions' (a face's walk
    extrapolated off the box under multisampling, -80 where the data lie in
    0..1) spread it so thin that every pixel of the picture came out up to
    10 grey off under a MinIP's narrow window.

    Examples
    --------
    >>> from mipcast.offscreen import grey_property
    >>> colour(np.array([[0.0, 0.5, np.nan]]), grey_property((0.0, 1.0)))[0, :, 0].round(3).tolist()
    [0.0, 0.5, 0.0]
    """
    values = np.asarray(values, dtype=np.float64)
    hit = ~np.isnan(values)
    out = np.zeros(values.shape + (4,), dtype=np.float32)
    if not hit.any():
        return out
    rgb_function = volume_property.GetRGBTransferFunction(0)
    opacity_function = volume_property.GetScalarOpacity(0)
    low, high = float(values[hit].min()), float(values[hit].max())
    if rgb_function.GetClamping() and opacity_function.GetClamping():  # constant beyond their points
        ranges = np.array([rgb_function.GetRange(), opacity_function.GetRange()])
        low, high = max(low, float(ranges[:, 0].min())), min(high, float(ranges[:, 1].max()))
    if high <= low:  # (np.interp holds the table's end values beyond it)
        high = low + 1.0
    samples = np.linspace(low, high, _TABLE)
    rgb_table = np.zeros(_TABLE * 3)
    rgb_function.GetTable(low, high, _TABLE, rgb_table)
    opacity_table = np.zeros(_TABLE)
    opacity_function.GetTable(low, high, _TABLE, opacity_table)
    flat = values[hit]
    alpha = np.interp(flat, samples, opacity_table)
    rgb = np.stack([np.interp(flat, samples, rgb_table[c::3]) for c in range(3)], axis=-1)
    out[hit, :3] = rgb * alpha[:, None]
    out[hit, 3] = alpha
    return out


def _draw_picture(mapper, renderer, volume, values, rgba=None) -> None:
    """Draw the coloured values (or the premultiplied ``rgba``) over the renderer's viewport, blended.

    With multisampling the picture is drawn face by face through the whole
    box's front faces (:func:`mipcast.mappers.box_outline.front_faces`), so
    the silhouette's pixels are blended by the box's coverage as the single
    texture's are, and each face's texture gives the pixels within a pixel of
    the face whose centre lies off it (off the box, or on the next face) what
    that face's fragment of the single texture reads there (:func:`_face_values`;
    DEMIP's ``rgba``: :func:`mipcast.mappers.bricked_demip.face_picture`).  The faces are drawn at their own depth with the
    depth test, so opaque geometry hides their samples as it hides the single
    texture's.  Otherwise (no multisampling, tiles, a box reaching the camera)
    over the whole viewport.
    """
    state = object_state(mapper)
    window = renderer.GetRenderWindow()
    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    faces = front_faces(box_corners(mapper.GetInput(), volume), renderer) if window.GetMultiSamples() > 1 else None
    outlines = [None]  # None: the whole viewport
    if rgba is not None:  # DEMIP's picture
        colours = [rgba]
        if faces:
            from mipcast.mappers.bricked_demip import face_picture

            colours = [face_picture(mapper, volume, renderer, rgba, face, _next_to(quad, values.shape))
                       for face, quad in faces]
            outlines = [[quad] for _, quad in faces]
    else:
        pictures = [values]
        if faces:
            pictures = [_face_values(mapper, volume, renderer, values, face, _next_to(quad, values.shape))
                        for face, quad in faces]
            outlines = [[quad] for _, quad in faces]
        colours = list(colour(np.stack(pictures), volume.GetProperty()))  # one colour table for all of them
    for index, (rgba, outline) in enumerate(zip(colours, outlines)):
        texture = kept_texture(state, ("brick_texture", index), window)
        data = np.ascontiguousarray(rgba[::-1], dtype=np.float32)  # bottom row first
        texture.Create2DFromRaw(values.shape[1], values.shape[0], 4, VTK_FLOAT, data)
        quads = None if outline is None else [
            ([c for x, y, _ in quad for c in (0.5 * (x + 1.0), 0.5 * (y + 1.0))], [c for point in quad for c in point])
            for quad in outline]
        # the faces at their own depth: opaque geometry in front hides their samples, as the single texture's
        draw_over(window, texture, (x0[0], y0[0], width[0], height[0]), quads, depth_test=outline is not None)


def _next_to(quad, shape) -> np.ndarray:
    """Pixels (rows, columns; top row first) whose centre lies outside the NDC ``quad`` ((x, y, z) corners, convex,
    counter-clockwise) but within a pixel of it: multisampling may cover some of their samples."""
    rows, columns = shape
    y, x = np.mgrid[0:rows, 0:columns]
    px, py = x + 0.5, rows - y - 0.5  # pixel units, from the viewport's lower left corner
    corners = [(0.5 * (qx + 1.0) * columns, 0.5 * (qy + 1.0) * rows) for qx, qy, *_ in quad]
    beyond = np.full(shape, -np.inf)  # the largest distance beyond an edge's line
    for (ax, ay), (bx, by) in zip(corners, corners[1:] + corners[:1]):
        length = np.hypot(bx - ax, by - ay)
        if length > 0.0:
            beyond = np.maximum(beyond, ((px - ax) * (by - ay) - (py - ay) * (bx - ax)) / length)
    return (beyond > 0.0) & (beyond <= 1.0)


#: The float64 kernels of the cell walks' rays off the box (extrapolated), per ``BRICKS``.
_WALKS = {"max": "exact_maximum", "min": "exact_minimum", "mean": "exact_mean"}


def _face_values(mapper, volume, renderer, values, face, pixels) -> np.ndarray:
    """``values`` with the ``pixels``' as the single texture's fragment of ``face`` gives them.

    The rays of :func:`mipcast.mappers.outline_rays.face_rays`, ended at
    opaque geometry and clipped as the loops clip
    (:func:`mipcast.mappers.outline_rays.face_samples`,
    :func:`~mipcast.mappers.outline_rays.face_walks`), combined as the method
    combines its samples (sampled: the maximum, the minimum, the mean of the
    samples in ``AverageIPScalarRange`` as ``shaders/average_hooks.glsl``) or cells (the float64 reference's exact
    kernels, extrapolating off the box).
    """
    from mipcast import reference

    step, sampled = object_state(mapper)["brick_sampling"]
    rule = type(mapper).BRICKS
    out = values.copy()
    if not pixels.any():
        return out
    image = placed(mapper.GetRenderedInput(), volume.GetMatrix())  # the volume's matrix folded in
    prepared = _prepared(mapper)
    if not sampled:
        # the mean over the finite part (NaN: none), bounded as the GPU bounds it with missing values
        floor = {"floor": prepared.missing_below, "bounded": True} if rule == "mean" and prepared.missing else {}
        rows, columns, found = outline_rays.face_walks(mapper, renderer, image, values.shape, step, face, pixels,
                                                       getattr(reference.mip, _WALKS[rule]), **floor)
        if rule != "mean":  # the mean's walk is bounded at the finite floor already
            found = prepared.seen(found)
    else:
        rows, columns, _, _, samples = outline_rays.face_samples(mapper, renderer, image, values.shape, step, face,
                                                                 pixels)
        if rule == "max":
            found = prepared.seen(np.fmax.reduce(samples, axis=1))
        elif rule == "min":
            found = prepared.seen(np.fmin.reduce(samples, axis=1))
        else:
            found = _sample_mean(mapper, samples)
    out[rows, columns] = found
    return out

"""Foveated levels beyond the GPU's 3D texture limit: composited over bricks first, then masked and blended.

A :class:`mipcast.mappers.foveated.FoveatedVolumeMapper` draws each pyramid
level with a private mapper of its layer method; a level whose volume (level
0 is the input itself, coarser levels its max-reduced copies) has more
points along an axis than the texture limit
(:func:`mipcast.mappers.bricked_draw.texture_limit`) cannot be uploaded.
Such a level is drawn in two steps inside the same render:

1. its rays' values are composited over the bricks of its volume:
   :func:`mipcast.mappers.bricked_draw.compose` with a private mapper of the
   layer method (the level's sample distance, image sample distance,
   component, cropping, clipping, matrix and property), every brick casting
   the WHOLE level volume's rays on the level's ray grid (VTK's reduced
   framebuffer of the level's image sample distance), combined by the
   maximum: exact for MIP and analytic MIP (``BRICKS`` ``"max"``), the
   maximum over disjoint sample or cell sets being the maximum over their
   union;
2. the composited values are drawn by the level's own foveation pieces: a
   level mapper whose hook piece (``shaders/foveated_brick_hooks.glsl``)
   marches no sample but reads the ray's value from a float texture of the
   level's grid, over a 2 x 2 x 2 box of the level volume's bounds and
   scalar range (so VTK rasters the same fragments and colours through the
   same tables).  The cast range, the content-adaptive mask (built from the
   composited coarse level's picture, as for one texture), the silhouette
   band and the blend weights are the level's own: the levels blend after
   compositing, never before (a maximum of blends is no blend of maxima).

A DEMIP layer (``BRICKS`` ``"demip"``) composites each too-large level over
its bricks as the DEMIP mapper does beyond the limit
(:func:`mipcast.mappers.bricked_demip.compose`, here on the level's ray grid
and its sample distance, the bricks casting only the level's rays): the
MAX of the bricks' maxima, the MIN of their whole-ray indices of the first
same-material sample, then depth (over the level volume's whole box),
Eq. 1 and the sphere on the CPU.  The level then draws from two float
textures of its grid (``shaders/foveated_brick_hooks.glsl``): the
maximum (its float readout) and the premultiplied DEMIP colour
(``shaders/foveated_brick_color.glsl``), masked and blended by the level's
own pieces as the colour ``demip_color`` writes for one texture.

Levels whose volume fits one texture are drawn as usual.  Every foveation
layer draws in bricks (:func:`refusal` refuses a layer method whose
``BRICKS`` is neither ``"max"`` nor ``"demip"``, should one be registered).

Examples
--------
>>> from mipcast.data_fixtures import make_fixture
>>> box = value_box(make_fixture("spheres", size=8))
>>> box.GetDimensions(), box.GetPointData().GetScalars().GetRange(0) == make_fixture(
...     "spheres", size=8).GetPointData().GetScalars().GetRange(0)
((2, 2, 2), True)
"""
from __future__ import annotations

from typing import Optional, Sequence

import numpy as np
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_FLOAT, VTK_OBJECT, vtkDataArray
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkVolume

from mipcast.core.object_state import object_state
from mipcast.core.parameter_tables import FOVEATION_LAYERS
from mipcast.mappers import bricked_draw, float_readout
from mipcast.mappers.private_draw import kept_texture

#: The hook piece of a level drawn from composited values (a DEMIP level's colours too).
HOOKS = "foveated_brick_hooks"
#: The colour piece of a DEMIP level drawn from composited values and colours.
COLOUR = "foveated_brick_color"
#: The layer methods' ``BRICKS`` whose levels draw beyond the texture limit.
BRICKED = ("max", "demip")
#: The value a ray without any brick's sample gets (what the sampled loop starts from).
_NO_VALUE = -1.0e30


def level_limit(mapper, level_input) -> int:
    """The texture limit when ``level_input`` (a foveated level's volume) exceeds it along an axis, else 0.

    Examples
    --------
    >>> from mipcast.mappers.foveated import FoveatedVolumeMapper
    >>> level_limit(FoveatedVolumeMapper(), vtkImageData())   # no window yet: limit unknown
    0
    """
    limit = bricked_draw.texture_limit(mapper)
    if limit < 2 or level_input is None:
        return 0
    return limit if max(level_input.GetDimensions()) > limit else 0


def refusal(mapper, method: str) -> Optional[str]:
    """The message refusing ``mapper``'s input beyond the texture limit for a layer ``method`` that cannot brick.

    None when the input fits one texture, or the layer draws in bricks
    (``BRICKS`` in :data:`BRICKED`: MIP, analytic MIP and DEMIP).

    Examples
    --------
    >>> from mipcast.mappers.foveated import FoveatedVolumeMapper
    >>> refusal(FoveatedVolumeMapper(), "demip") is None
    True
    """
    if getattr(FOVEATION_LAYERS[method].factory, "BRICKS", None) in BRICKED:
        return None
    limit = bricked_draw.exceeds_limit(mapper)
    if not limit:
        return None
    dims = mapper.GetInputPreparer().GetInputDataObject(0, 0).GetDimensions()
    layers = ", ".join(name for name, entry in FOVEATION_LAYERS.items()
                       if getattr(entry.factory, "BRICKS", None) in BRICKED)
    return (f"the volume's dimensions {dims} exceed this GPU's 3D texture limit of {limit} points per "
            f"axis, and the foveated mapper cannot draw its {method!r} levels in bricks (their ray value over "
            "several bricks is not known from the bricks'): resample the volume to at most "
            f"{limit} points per axis (e.g. vtkImageResample), crop it (vtkExtractVOI), use foveation "
            f"layers that draw in bricks (SetMethod: {layers}), or the {method!r} method itself unfoveated")


def value_box(rendered) -> vtkImageData:
    """A 2 x 2 x 2 image of ``rendered``'s bounds, direction and scalar type holding its scalar range.

    What a level drawn from composited values rasters (the same box, so the
    same fragments) and normalises with (the same range, so the same colour
    tables and readout units).
    """
    dims = rendered.GetDimensions()
    box = vtkImageData()
    box.SetDimensions(2, 2, 2)
    box.SetOrigin(rendered.GetPoint(0))  # the first point of the extent (which may not start at 0)
    box.SetSpacing([s * max(d - 1, 1) for s, d in zip(rendered.GetSpacing(), dims)])
    box.SetDirectionMatrix(rendered.GetDirectionMatrix())
    scalars = rendered.GetPointData().GetScalars()
    array = vtkDataArray.CreateDataArray(scalars.GetDataType())
    array.SetName(scalars.GetName() or "scalars")
    array.SetNumberOfComponents(1)
    array.SetNumberOfTuples(8)
    low, high = scalars.GetRange(0)
    for index in range(8):
        array.SetTuple1(index, high if index == 7 else low)
    box.GetPointData().SetScalars(array)
    return box


#: Pieces a level's bricks add to their method's: they cast only where the level casts (its cast
#: range and silhouette band; a superset of a content-adaptive level's rays), no blend weight.
SOURCE_PIECES = ("foveated_band_dec", "foveated_skip")
_SOURCE_CLASSES: dict = {}


def source_class(base) -> type:
    """``base`` (a layer method's mapper class) whose rays are cast only where a foveated level casts.

    Examples
    --------
    >>> from mipcast.mappers.mip import MIPVolumeMapper
    >>> source_class(MIPVolumeMapper)().GetShaderPieces()[-2:]
    ('foveated_band_dec', 'foveated_skip')
    """
    cls = _SOURCE_CLASSES.get(base)
    if cls is None:
        def GetShaderPieces(self):
            return tuple(base.GetShaderPieces(self)) + SOURCE_PIECES

        cls = type(f"FoveatedBrick{base.__name__}", (base,), {
            "__doc__": f"{base.__name__} casting only a foveated level's rays (a brick's source).",
            "GetShaderPieces": GetShaderPieces})
        _SOURCE_CLASSES[base] = cls
    return cls


def level_source(state, volume_level: int, method: str) -> dict:
    """The private mapper of the layer method (on its own vtkVolume) whose bricks a level composites."""
    sources = state.setdefault("brick_sources", {})
    entry = sources.get(volume_level)
    if entry is None or entry["method"] != method:
        from vtkmodules.vtkCommonMath import vtkMatrix4x4

        source = source_class(FOVEATION_LAYERS[method].factory)()
        source_volume = vtkVolume()
        source.Attach(source_volume)
        entry = sources[volume_level] = {"mapper": source, "volume": source_volume, "matrix": vtkMatrix4x4(),
                                         "method": method}
    return entry


def composite(source: dict, volume, renderer, limit: int, image_sample_distance: float,
              grid: Sequence[int]) -> np.ndarray:
    """The level's rays composited over its bricks: data units, (rows, columns) top row first, NaN = no value."""
    gl = renderer.GetRenderWindow().GetState()
    gl.Push()  # the bricks' render-to-image passes set their own viewport and framebuffer
    try:
        return bricked_draw.compose(source["mapper"], volume, renderer, limit,
                                    image_sample_distance=image_sample_distance, grid=grid)
    finally:
        gl.Pop()


def is_demip(method: str) -> bool:
    """Whether the layer ``method`` composites its bricks as DEMIP (:mod:`mipcast.mappers.bricked_demip`).

    Examples
    --------
    >>> is_demip("demip"), is_demip("mip")
    (True, False)
    """
    return getattr(FOVEATION_LAYERS[method].factory, "BRICKS", None) == "demip"


def demip_bricks(source: dict, limit: int) -> list:
    """The DEMIP bricks (phase 1, phase 2 entries) of a level's source, casting only the level's rays."""
    from mipcast.mappers import bricked_demip

    return bricked_demip.bricks_of(source["mapper"], limit, source_class)


def composite_demip(source: dict, volume, renderer, limit: int, image_sample_distance: float,
                    grid: Sequence[int]):
    """The level's DEMIP composited over its bricks on its ray grid: (values, premultiplied RGBA).

    ``values``: the whole-ray maximum in data units (NaN: no value), (rows,
    columns) top row first; ``rgba``: (rows, columns, 4), float, 0 where
    the ray has no value.
    """
    from mipcast.mappers import bricked_demip

    gl = renderer.GetRenderWindow().GetState()
    gl.Push()  # the bricks' render-to-image passes set their own viewport and framebuffer
    try:
        values, _, rgba = bricked_demip.compose(source["mapper"], volume, renderer, limit,
                                                image_sample_distance=image_sample_distance, grid=grid,
                                                kinds=source_class)
    finally:
        gl.Pop()
    return values, rgba


def level_texture(state, renderer, level: int, data: np.ndarray, kind: str):
    """A level's composited ``data`` (rows x columns [x 4], top row first) as a nearest-filtered float texture.

    ``kind``: ``"values"`` (one channel: :func:`normalised_values`) or
    ``"colours"`` (RGBA, premultiplied); one texture per level and kind.
    """
    textures = state.setdefault(f"{kind}_textures", {})
    window = renderer.GetRenderWindow()
    texture = kept_texture(textures, level, window)
    data = np.ascontiguousarray(np.nan_to_num(data)[::-1], dtype=np.float32)  # bottom row first
    rows, columns = data.shape[:2]
    texture.Create2DFromRaw(columns, rows, data.shape[2] if data.ndim == 3 else 1, VTK_FLOAT, data)
    return texture


def normalised_values(values: np.ndarray, rendered) -> np.ndarray:
    """Composited values (data units) as the level's shader holds them: VTK's normalised scalar, float32.

    Rays without a value get -1e30 (the sampled loop's start: no sample).
    """
    normalised = float_readout.from_data_units(values, rendered.GetPointData().GetScalars())
    return np.where(np.isfinite(values), normalised, _NO_VALUE).astype(np.float32)


@calldata_type(VTK_OBJECT)
def bind_values_sampler(level_mapper, event, program) -> None:
    """UpdateShaderEvent: point ``u_mc_fovValues`` (and a DEMIP level's ``u_mc_fovColours``) at their units."""
    level_state = object_state(level_mapper)
    unit = level_state.get("values_unit")
    colours = level_state.get("colours_unit")
    if program is not None and unit is not None and unit >= 0 and (colours is None or colours >= 0):
        program.SetUniformi("u_mc_fovValues", int(unit))
        if colours is not None:
            program.SetUniformi("u_mc_fovColours", int(colours))
        level_state["samplers_set"] = True

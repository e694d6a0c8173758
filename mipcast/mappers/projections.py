"""Minimum and average intensity projections, sampled and exact.

The sampled ones are one hook piece each for the one sampled loop
(``shaders/minip_hooks.glsl``, ``shaders/average_hooks.glsl``, through
:func:`mipcast.mappers.mip.sampled_projection_mapper`); the exact ones walk
the cells as analytic MIP does, with other cell hooks
(``shaders/amip_min_hooks.glsl``: the exact minimum of each cell's cubic;
``shaders/amip_average_hooks.glsl``: the integral of each cubic over its
segment; with missing values, over the part where it is finite).  Each colours its value through the volume property's colour and
opacity transfer functions, as MIP colours its maximum, so the window and the
colour map apply: MinIP its minimum (as VTK's MINIMUM_INTENSITY blend), the
average its mean (the sampled one over the samples in
``AverageIPScalarRange``, as VTK's AVERAGE_INTENSITY blend counts them; VTK's
own average draws instead a grey of the opacity-weighted mean normalised over
the data range, ignoring the window and colours).

See docs/methods.md, sections MinIP and Average.

Examples
--------
>>> MinIPVolumeMapper().GetShaderPieces()[3]
'minip_hooks'
>>> "amip_min_hooks" in AnalyticMinIPVolumeMapper().GetShaderPieces()
True
"""
from __future__ import annotations

from vtkmodules.vtkCommonCore import vtkFloatArray

from mipcast.core import parameter_tables
from mipcast.core.parameters import parameter_accessors
from mipcast.mappers.analytic import AnalyticMIPVolumeMapper
from mipcast.mappers.float_readout import from_data_units
from mipcast.mappers.mip import sampled_projection_mapper

#: Normalised bounds beyond any value (VTK's default AverageIPScalarRange is all floats).
_FAR = 1.0e30


@parameter_accessors
class MinIPVolumeMapper(sampled_projection_mapper("minip_hooks")):
    """Sampled minimum intensity projection: the smallest of stock VTK's samples.

    The same samples as stock VTK's MINIMUM_INTENSITY blend (``entry + i *
    step``), coloured through the volume property's colour and opacity
    transfer functions like MIP.  With a window whose ceiling lies below the
    data maximum (lung, airways) each ray starts at the ceiling, jumps over
    blocks of cells whose minimum is not below its running minimum and stops
    at the floor (``SetSkipping``; the same picture).  Attach it with
    :meth:`Attach`.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> mapper = MinIPVolumeMapper()
    >>> volume = vtkVolume()
    >>> mapper.Attach(volume)
    >>> mapper.IsAttached()
    True
    """

    MISSING_FILL = "above"  # a missing voxel is never the minimum
    MISSING_PIECE = "missing_exit_above"
    #: The minimum over bricks is the minimum (:mod:`mipcast.mappers.bricked_draw`).
    BRICKS = "min"
    BLOCK_EXTREME = "min"
    PARAMETERS = parameter_tables.MINIP


class AverageVolumeMapper(sampled_projection_mapper("average_hooks", color="average_color")):
    """Sampled average intensity projection: the mean of stock VTK's samples, coloured like MIP.

    Samples at stock's positions whose value lies in the mapper's
    ``AverageIPScalarRange`` (VTK's setting, default every value) count, as
    in stock's AVERAGE_INTENSITY blend; the ray's value is their plain mean
    (the float readout, in data units), coloured through the volume
    property's colour and opacity transfer functions as MIP colours its
    maximum, so the window and colour map apply (stock draws a grey of the
    opacity-weighted mean normalised over the data range instead).

    Examples
    --------
    >>> mapper = AverageVolumeMapper()
    >>> mapper.SetAverageIPScalarRange(0.2, 0.8)
    >>> mapper.GetShaderPieces()[-1]
    'average_color'
    """

    #: Missing voxels: filled below the data; samples the fill pulled below
    #: the finite minimum do not count (the average's scalar range starts
    #: there), a ray with no sample left draws nothing (average_color).
    MISSING_PIECE = None
    #: Over bricks: the bricks' means weighted by the number of samples each counted (bricks take
    #: the whole volume's samples, each in one brick: :mod:`mipcast.mappers.bricked_draw`).
    BRICKS = "mean"
    BRICK_READOUT = "average_brick_readout"

    def _push_derived_uniforms(self, uniforms, settings) -> None:
        super()._push_derived_uniforms(uniforms, settings)
        image = self.GetRenderedInput()  # the drawn values: missing ones filled, one component
        scalars = image.GetPointData().GetScalars() if image is not None else None
        low, high = self.GetAverageIPScalarRange()
        if scalars is None:
            scalars = vtkFloatArray()
        ends = [max(-_FAR, min(_FAR, float(v))) for v in from_data_units([low, high], scalars)]
        bottom = -_FAR if low <= -3.0e38 else ends[0]
        missing = self._missing_below()
        if missing is not None:  # the mean over the finite part of the ray (docs/methods.md)
            bottom = max(bottom, missing)
        uniforms.SetUniformf("u_mc_averageLow", bottom)
        uniforms.SetUniformf("u_mc_averageHigh", _FAR if high >= 3.0e38 else ends[1])


def _exact_pieces(hooks: str, color=None) -> tuple:
    """Analytic MIP's pieces with the cell hooks ``hooks`` (and colour piece ``color``)."""
    swap = {"amip_max_hooks": hooks}
    if color is not None:
        swap.update(mip_color=color)
    return tuple(swap.get(n, n) for n in AnalyticMIPVolumeMapper.PIECES)


class _ExactProjection(AnalyticMIPVolumeMapper):
    """Analytic MIP's cell walk with other cell hooks; block skipping where :data:`BLOCK_EXTREME` says
    what a block's bound is (the exact MinIP: its minimum)."""

    #: Over bricks: none by default (the average's sum of integrals over the ray's length is not
    #: a maximum); the exact MinIP takes the minimum.
    BRICKS = None
    #: No block level by default (every cell counts in an average).
    BLOCK_EXTREME = None


class AnalyticMinIPVolumeMapper(_ExactProjection):
    """Exact MinIP: the minimum of the trilinear interpolant along the ray, cell by cell.

    Analytic MIP's walk with the mirrored bounds: the minimum of each cell's
    cubic (the maximum of the negated cubic), cells none of whose corners is
    below the running minimum skipped (``SetSkipping``), the walk starting at
    the transfer functions' ceiling and ending at their floor, and (with a
    ceiling below the data maximum) blocks whose minimum is not below the
    running minimum jumped over.  Sees thin dark structure (airways) between
    samples that sampled MinIP steps over.

    Examples
    --------
    >>> AnalyticMinIPVolumeMapper().GetSkipping()
    True
    """

    MISSING_FILL = "above"  # a missing voxel is never the minimum
    MISSING_PIECE = "missing_exit_above"
    BRICKS = "min"
    BLOCK_EXTREME = "min"

    PIECES = _exact_pieces("amip_min_hooks")


class AnalyticAverageVolumeMapper(_ExactProjection):
    """Exact average: the mean of the trilinear interpolant along the ray inside the volume.

    Per crossed cell the integral of its cubic times the segment length,
    summed and divided by the ray's length; coloured through the volume
    property's transfer functions as MIP colours its maximum.  Every cell
    counts, so ``SetSkipping`` changes nothing; ``AverageIPScalarRange`` has
    no exact counterpart (it would need the roots of ``f(s) = bound``) and is
    not applied.

    Examples
    --------
    >>> AnalyticAverageVolumeMapper().GetShaderPieces()[-1]
    'average_color'
    """

    #: Missing voxels: filled below the data; only the part of the ray where
    #: the interpolant is at or above the finite minimum counts (amip_average_hooks'
    #: covered-part search, turned on by this piece only while the input holds
    #: missing values; u_mc_missingBelow); a ray with none draws nothing.
    MISSING_PIECE = "amip_average_missing"
    #: Over bricks: the bricks' means weighted by the length of the ray each counted
    #: (:mod:`mipcast.mappers.bricked_draw`).
    BRICKS = "mean"
    BRICK_READOUT = "amip_average_brick_readout"

    PIECES = _exact_pieces("amip_average_hooks", color="average_color")
    PACKED = {"amip_corners": "amip_corners_packed", "average_color": "average_color_packed"}

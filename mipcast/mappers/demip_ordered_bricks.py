"""DEMIP's ordered projections drawn in bricks: LMIP and attenuated MIP, brick after brick front to back.

LMIP (``projection="lmip"``, docs/methods.md#demip) scans the ray front to
back and ends it before the first sample that falls below a running maximum
above ``local_threshold``; the ray's value is that running maximum.  The
scan's state at a brick's border is the running maximum of the samples in
front of it (and whether the scan has already ended), so the bricks are
drawn in a front-to-back visibility order
(:func:`mipcast.mappers.brick_rays.visibility_order`) by
:class:`LMIPBrickMapper`: each reads the running maximum so far as a float
texture (per pixel, as :class:`mipcast.mappers.demip_brick.DEMIPBrickDepthMapper`
reads the global maximum), continues the scan over its share of the WHOLE
volume's samples (the ``global_phase`` piece: whole-ray positions and
indices, so a local maximum straddling a brick border is seen as one ray
sees it: the sample in front lies in the brick in front, the fall in the
brick behind, and the running maximum crosses with the texture) and reads
out the new running maximum (channel 0) and whether the scan ended in it
(channel 1).  A ray whose scan ended keeps its maximum: the bricks behind
do not touch it (:func:`scan`).  Phase 2 (the first same-material sample)
is DEMIP's: the maximum's own sample lies before the end, so the bricks'
minimum index is the shortened ray's first same-material sample.

Attenuated MIP (``projection="attenuated"``) weighs each sample's material
by ``exp(-decay * crossed)``, ``crossed`` the material of the samples in
front of it: :class:`AttenuatedBrickMapper` reads the crossed material so
far as the float texture, continues the single texture's sums over its
samples (the same float32 operations in the same order) and reads out its
best attenuated material and the crossed material after it, both exactly
as float32 (:func:`attenuated_scan`); the whole ray's best is the maximum
of the bricks' (no DEMIP term: no phase 2).

MIDA (``projection="mida"``) composites front to back with weights that
depend on the running maximum of the material: :class:`MIDABrickMapper`
reads the running material and accumulated opacity so far (a two-channel
float texture), continues the compositing over its samples and reads out
its colour (started at 0: MIDA's colour update is linear in the colour in
front), the opacity and running material after it and the product of its
betas (:func:`mida_scan` applies ``C = P C + C_brick``).  Only the picture
needs this; MIDA's float readout (the sampled maximum) is the MAX of the
bricks' MIP.

Each state texture also carries the scene depth in its alpha
(:func:`mipcast.mappers.demip_brick.upload_pixels`' ``depth``), where the
bricks' rays end at opaque geometry, as the whole volume's ray ends.

Examples
--------
>>> mapper = LMIPBrickMapper()
>>> "demip_brick_lmip_hooks" in mapper.GetShaderPieces()
True
"""
from __future__ import annotations

import numpy as np

from mipcast.core.transfer_bounds import constant_ends
from mipcast.mappers.demip_brick import NO_MAXIMUM, DEMIPBrickDepthMapper, upload_pixels
from mipcast.mappers.float_readout import from_data_units


class LMIPBrickMapper(DEMIPBrickDepthMapper):
    """One brick's part of LMIP's scan (phase 1 of bricked LMIP DEMIP), continued from the bricks in front.

    Needs ``global_box`` in its state and the brick's ``global_phase``
    uniforms (:func:`mipcast.mappers.brick_rays.brick_entry`), the running
    maximum so far (:func:`bind_running`) and ``u_mc_brickChannel`` on its
    volume's uniforms (0: the running maximum, 1: the end flag).

    Examples
    --------
    >>> LMIPBrickMapper().GetShaderPieces()[:2]
    ('mip_globals', 'demip_brick_fetch')
    """

    PIECES = ("mip_globals", "demip_brick_fetch", "demip_helpers", "sampled_loop", "demip_brick_lmip_hooks",
              "no_stock_sample", "mip_color")

    def GetShaderPieces(self) -> tuple:
        """:data:`PIECES` (with ``global_phase`` on a brick); the state readout while a readout renders."""
        names = self._with_readout(self.PIECES)
        return self._with_missing("demip_brick_lmip_readout" if n == "float_readout" else n for n in names)


class AttenuatedBrickMapper(DEMIPBrickDepthMapper):
    """One brick's part of attenuated MIP, continued from the material crossed in the bricks in front.

    As :class:`LMIPBrickMapper`; its state is the crossed material
    (:func:`bind_crossed`); channel 0 reads out minus the best attenuated
    material, channel 1 minus the crossed material after the brick.

    Examples
    --------
    >>> "demip_brick_attenuated_hooks" in AttenuatedBrickMapper().GetShaderPieces()
    True
    """

    PIECES = ("mip_globals", "demip_brick_fetch", "demip_helpers", "sampled_loop",
              "demip_brick_attenuated_hooks", "no_stock_sample", "mip_color")
    #: No per-brick missing test: its mc_rayMax is a material, not a scalar; the whole ray's test is the
    #: CPU's, on the attenuated value (:func:`mipcast.mappers.bricked_demip.compose`).
    MISSING_PIECE = None

    def GetShaderPieces(self) -> tuple:
        """:data:`PIECES` (with ``global_phase`` on a brick); the raw readout while a readout renders."""
        names = self._with_readout(self.PIECES)
        return self._with_missing("demip_brick_attenuated_readout" if n == "float_readout" else n for n in names)


class MIDABrickMapper(DEMIPBrickDepthMapper):
    """One brick's part of MIDA's compositing, continued from the state the bricks in front left.

    Its state (:func:`bind_mida`): running material and accumulated opacity;
    ``u_mc_brickChannel`` 0 .. 5 reads out (minus) the brick's colour (r, g,
    b), the opacity, the product of its betas and the running material.

    Examples
    --------
    >>> "demip_brick_state_fetch" in MIDABrickMapper().GetShaderPieces()
    True
    """

    PIECES = ("mip_globals", "demip_brick_state_fetch", "demip_helpers", "sampled_loop",
              "demip_brick_mida_hooks", "no_stock_sample", "mip_color")
    #: No per-brick missing test (its mc_rayMax is 0): the whole ray's is the CPU's, on the bricks' MAX.
    MISSING_PIECE = None

    def GetShaderPieces(self) -> tuple:
        """:data:`PIECES` (with ``global_phase`` on a brick); the state readout while a readout renders."""
        names = self._with_readout(self.PIECES)
        return self._with_missing("demip_brick_mida_readout" if n == "float_readout" else n for n in names)


#: MIDA's readout channels (``u_mc_brickChannel``), in order.
MIDA_CHANNELS = ("red", "green", "blue", "opacity", "beta_product", "material")


def bind_mida(render_window, mapper: MIDABrickMapper, material: np.ndarray, opacity: np.ndarray,
              data_range, depth=None) -> None:
    """MIDA's state so far on ``mapper`` (running material, accumulated opacity) and the material window;
    ``depth``: the scene depth its rays end at (:func:`mipcast.mappers.demip_brick.upload_pixels`)."""
    _bind_window(mapper, data_range)
    upload_pixels(render_window, mapper, np.stack([material, opacity], axis=-1), depth)


def mida_scan(colour: np.ndarray, opacity: np.ndarray, material: np.ndarray, readouts: dict) -> None:
    """One brick's readouts (:data:`MIDA_CHANNELS` -> minus the value, +1 where no ray) into the state, in place.

    Examples
    --------
    >>> colour, opacity, material = np.zeros((1, 2, 3)), np.array([[0.5, 0.2]]), np.array([[0.4, 0.1]])
    >>> out = {"red": np.array([[-0.1, 1.0]]), "green": np.array([[-0.2, 1.0]]), "blue": np.array([[-0.3, 1.0]]),
    ...        "opacity": np.array([[-0.6, 1.0]]), "beta_product": np.array([[-0.5, 1.0]]),
    ...        "material": np.array([[-0.7, 1.0]])}
    >>> colour[0, 0] = 0.2
    >>> mida_scan(colour, opacity, material, out)
    >>> colour[0].round(3).tolist(), opacity.tolist(), material.tolist()
    ([[0.2, 0.3, 0.4], [0.0, 0.0, 0.0]], [[0.6, 0.2]], [[0.7, 0.1]])
    """
    drawn = readouts["opacity"] != 1.0
    value = {name: -np.asarray(readout, dtype=np.float64) for name, readout in readouts.items()}
    brick = np.stack([value["red"], value["green"], value["blue"]], axis=-1)
    colour[drawn] = (value["beta_product"][..., None] * colour + brick)[drawn]
    opacity[drawn] = value["opacity"][drawn]
    material[drawn] = value["material"][drawn]


def _bind_window(mapper, data_range) -> None:
    """The material window (the transfer functions' ends over the whole range) in the brick's scalar."""
    scalars = mapper.GetRenderedInput().GetPointData().GetScalars()
    floor, ceiling = constant_ends(mapper.GetAttachedVolume().GetProperty(), *data_range)
    floor, ceiling = (float(v) for v in from_data_units(np.array([floor, ceiling]), scalars))
    if not ceiling > floor:  # constant transfer functions: no material anywhere (as DEMIPVolumeMapper's window)
        floor, ceiling = 1.0e20, 2.0e20
    mapper.GetAttachedVolume().GetShaderProperty().GetFragmentCustomUniforms().SetUniform4f(
        "u_mc_brickWindow", [floor, ceiling, 0.0, 0.0])


def bind_crossed(render_window, mapper: AttenuatedBrickMapper, crossed: np.ndarray, data_range,
                 depth=None) -> None:
    """The crossed material so far (per pixel, float32 as the GPU summed it) and the material window;
    ``depth``: the scene depth its rays end at (:func:`mipcast.mappers.demip_brick.upload_pixels`)."""
    _bind_window(mapper, data_range)
    upload_pixels(render_window, mapper, crossed, depth)


def attenuated_value(best: np.ndarray, volume_property, data_range) -> np.ndarray:
    """The ray's value in data units: the scalar of the best attenuated material (NaN: no sample).

    Examples
    --------
    >>> from mipcast.offscreen import grey_property
    >>> attenuated_value(np.array([0.5, np.nan]), grey_property((100.0, 300.0)), (0.0, 1000.0)).tolist()
    [200.0, nan]
    """
    floor, ceiling = constant_ends(volume_property, *data_range)
    return floor + np.asarray(best, dtype=np.float64) * (ceiling - floor)


def local_threshold(volume_property, data_range, fraction: float) -> float:
    """LMIP's threshold in data units: ``fraction`` of the transfer functions' window over ``data_range``.

    As the single texture's (``floor + fraction (ceiling - floor)``, the
    window's ends those of :func:`mipcast.core.transfer_bounds.constant_ends`).

    Examples
    --------
    >>> from mipcast.offscreen import grey_property
    >>> local_threshold(grey_property((100.0, 300.0)), (0.0, 1000.0), 0.5)
    200.0
    """
    floor, ceiling = constant_ends(volume_property, *data_range)
    if not ceiling > floor:
        return float("inf")  # no window: no sample is above it, the scan never ends (the global maximum)
    return float(floor + fraction * (ceiling - floor))


def bind_running(render_window, mapper: LMIPBrickMapper, running: np.ndarray, local: float, depth=None) -> None:
    """The scan's state on ``mapper``: the running maximum so far (data units, NaN: none) and the threshold;
    ``depth``: the scene depth its rays end at (:func:`mipcast.mappers.demip_brick.upload_pixels`)."""
    scalars = mapper.GetRenderedInput().GetPointData().GetScalars()
    normalised = np.where(np.isnan(running), NO_MAXIMUM, from_data_units(np.nan_to_num(running), scalars))
    threshold = float(from_data_units(np.array([local]), scalars)[0]) if np.isfinite(local) else 1.0e30
    mapper.GetAttachedVolume().GetShaderProperty().GetFragmentCustomUniforms().SetUniformf(
        "u_mc_brickLocal", threshold)
    upload_pixels(render_window, mapper, normalised, depth)


def scan(running: np.ndarray, ended: np.ndarray, brick_max: np.ndarray, brick_ended: np.ndarray) -> None:
    """One brick's readouts into the scan's state, in place: rays not yet ended take the brick's.

    ``brick_max`` in data units (NaN: the brick's ray had no sample and
    no state), ``brick_ended`` 1 where the scan ended in the brick.

    Examples
    --------
    >>> running, ended = np.array([1.0, 2.0, np.nan]), np.array([False, True, False])
    >>> scan(running, ended, np.array([3.0, 5.0, np.nan]), np.array([1.0, 0.0, np.nan]))
    >>> running.tolist(), ended.tolist()
    ([3.0, 2.0, nan], [True, True, False])
    """
    open_ = ~ended & ~np.isnan(brick_max)
    running[open_] = brick_max[open_]
    ended |= open_ & (np.nan_to_num(brick_ended) > 0.5)

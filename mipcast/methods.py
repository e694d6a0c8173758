"""The method table: every rendering method, defined once.

Each :class:`Method` names its mapper factory, its float64 reference, its
parameter table (:mod:`mipcast.core.parameter_tables`) and what it can do.
The command line's ``--method`` choices and help, the pyvista accessors and
plotter component, the viewer's method cycle and sliders, ParaView's entries,
the benchmark's settings, the stability cases and the tests all iterate over
:data:`METHODS`; nothing else asks a mapper what it can do.

Adding a method is one entry here (plus its mapper or GLSL piece and its
reference function): see :func:`register`.

Examples
--------
>>> list(METHODS)[:3]
['stock', 'mip', 'analytic']
>>> METHODS["analytic"].walks_cells, METHODS["analytic"].float_readout
(True, True)
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Dict, Optional, Tuple

import numpy as np
from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast import reference
from mipcast.core import parameter_tables
from mipcast.core.parameter_tables import FOVEATION_LAYERS
from mipcast.core.parameters import Parameter
from mipcast.core.validation import check_choice
from mipcast.mappers.analytic import AnalyticMIPVolumeMapper
from mipcast.mappers.demip import DEMIPVolumeMapper
from mipcast.mappers.demip_two_pass import DEMIPTwoPassVolumeMapper
from mipcast.mappers.foveated import FoveatedVolumeMapper
from mipcast.mappers import shader_pieces
from mipcast.mappers.mip import MIPVolumeMapper
from mipcast.mappers.projections import (AnalyticAverageVolumeMapper, AnalyticMinIPVolumeMapper,
                                         AverageVolumeMapper, MinIPVolumeMapper)


@dataclass(frozen=True)
class Method:
    """One rendering method: what it is, how to make it, how to check it, what it can do.

    Parameters
    ----------
    name : str
        The name users type (``--method``, ``grid.mip.render(method)``).
    label : str
        A title for menus and charts.
    summary : str
        One line: what the picture shows.
    factory : callable
        ``factory()`` returns an unconfigured mapper (a class is a factory).
    reference : callable, optional
        The float64 picture its float readout must match:
        ``reference(image, camera, size, *, sample_distance, window, **params)``
        with the method's parameters (and ``component``, as the mappers'
        ``SetComponent``); None for methods without a float
        readout or whose picture depends on the gaze (foveation).
    reference_tolerance : float
        The largest error (fraction of the data range) of its float readout
        against ``reference`` on the test fixtures, for the accuracy test.
    parameters : tuple of Parameter
        The method's parameter table.
    float_readout : bool
        A mipcast shader-piece mapper: attached with ``Attach(volume)``, its
        per-pixel values readable in float (:func:`mipcast.mappers.float_readout.render_float`).
    foveation_layer : bool
        A foveated mapper can draw its levels with it.
    walks_cells : bool
        It walks cells instead of sampling: no sample distance (no slider,
        no ``--sample-distance``).
    in_view : bool
        It renders in an interactive view (ParaView's representation, the viewer).
    readout_by : str, optional
        A method without a float readout whose samples another method's
        readout reproduces exactly (stock VTK MIP: mipcast's ``"mip"``); the
        benchmark reads its error there.
    distributed : str, optional
        How bricks of a volume split across processes composite exactly
        (:mod:`mipcast.distributed`, its ``ROUTES``): ``"max"``, the maximum
        of the bricks' float readouts is the whole volume's; ``"demip"``, the
        MAX of the bricks' sampled MIP, then the MIN of the whole-ray index of
        the first sample of the global maximum's material (depth, Eq. 1 and
        sphere on the CPU); None: not distributed yet.
    rank_view : str, optional
        How a method without a ``distributed`` route composites exactly in a
        parallel ParaView render view (plugin/representation, ranks' pieces):
        ``"foveated"``, each foveated level's readouts reduced with MAX over the
        ranks (its coarse pyramid levels reduced from the pieces' shares), then
        blended (:mod:`mipcast.mappers.rank_foveated`; DEMIP layers refused);
        ``"depth"``, VTK's own GPU MIP / MinIP writing its ray's value as depth
        for IceT's Z-buffer compositing (:mod:`mipcast.mappers.stock_depth`;
        on the whole volume's sample positions); ``"mean"``, VTK's own average
        composited by the reduction of the pieces' sample counts and sums
        (:mod:`mipcast.mappers.rank_composite`, rule ``"mean"``), each piece
        read out by its ``readout_by`` mapper (the same samples and weights).
        Methods with none (and no ``distributed`` route nor ``bricks="mean"``)
        are refused in such a view.
    bricks : str, optional
        How its mapper draws a volume beyond the GPU's 3D texture limit inside
        one render (:mod:`mipcast.mappers.bricked_draw`; the mapper class's
        ``BRICKS``): ``"max"`` / ``"min"``, bricks combined by the maximum /
        minimum of their float readouts (exact); ``"demip"``, DEMIP's two
        phases over the bricks (:mod:`mipcast.mappers.bricked_demip`, as the
        ``"demip"`` distributed route); ``"mean"``, by their means weighted by
        the samples / ray length each brick counted (exact); ``"foveated"``, each
        level too large for one texture composited over its bricks by its layer
        method's maximum (a DEMIP layer: DEMIP's two phases), then masked and
        blended as one texture (:mod:`mipcast.mappers.bricked_foveated`); None: such
        a volume is refused with a message naming the limit and the fix.
    bench : tuple of (label, samples_per_voxel, settings), optional
        Its rows in ``mipcast bench``: ``settings`` are ``(Name, value)``
        pairs for its setters; default one row, the method's own name at one
        sample per voxel (no sampling rate if it walks cells).
    projection : str
        What its value along a ray is: ``"mip"`` (the maximum; DEMIP's value
        too), ``"minip"`` (the minimum) or ``"average"`` (the mean): its
        benchmark error is against that projection's exact float64 reference
        (:attr:`exact_reference`).
    """

    name: str
    label: str
    summary: str
    factory: Callable[[], Any]
    reference: Optional[Callable[..., np.ndarray]] = None
    reference_tolerance: float = 1e-3
    parameters: Tuple[Parameter, ...] = ()
    float_readout: bool = True
    foveation_layer: bool = False
    walks_cells: bool = False
    in_view: bool = True
    readout_by: Optional[str] = None
    distributed: Optional[str] = None
    rank_view: Optional[str] = None
    bricks: Optional[str] = None
    bench: Optional[Tuple[Tuple[str, Any, tuple], ...]] = None
    projection: str = "mip"

    @property
    def exact_reference(self) -> Callable[..., np.ndarray]:
        """The exact float64 reference of its projection (:data:`EXACT_REFERENCES`), for errors.

        Examples
        --------
        >>> METHODS["stock_minip"].exact_reference is exact_minip_reference
        True
        """
        return EXACT_REFERENCES[self.projection]

    def create(self):
        """A new, unconfigured mapper of this method."""
        return self.factory()

    def bench_rows(self) -> Tuple[Tuple[str, Any, tuple], ...]:
        """Its ``mipcast bench`` rows (see ``bench``)."""
        if self.bench is not None:
            return self.bench
        return ((self.name, None if self.walks_cells else 1, ()),)


# -- factories of VTK's own mappers --------------------------------------------
def _stock_mip() -> vtkOpenGLGPUVolumeRayCastMapper:
    mapper = vtkOpenGLGPUVolumeRayCastMapper()
    mapper.SetBlendModeToMaximumIntensity()
    return mapper


def _stock_minip() -> vtkOpenGLGPUVolumeRayCastMapper:
    mapper = vtkOpenGLGPUVolumeRayCastMapper()
    mapper.SetBlendModeToMinimumIntensity()
    return mapper


def _stock_average() -> vtkOpenGLGPUVolumeRayCastMapper:
    mapper = vtkOpenGLGPUVolumeRayCastMapper()
    mapper.SetBlendModeToAverageIntensity()
    return mapper


def _cpu_mip() -> vtkFixedPointVolumeRayCastMapper:
    mapper = vtkFixedPointVolumeRayCastMapper()
    mapper.SetBlendModeToMaximumIntensity()
    return mapper


def _demip_two_pass() -> DEMIPTwoPassVolumeMapper:
    # a factory, not the class: this comparison method is no foveation layer
    # (its private first pass would cast every ray at every level)
    return DEMIPTwoPassVolumeMapper()


# -- references, one signature ---------------------------------------------------
def projection_reference(name: str) -> Callable[..., np.ndarray]:
    """The float64 reference :func:`mipcast.reference.render` of ``name``, in the table's signature.

    ``reference(image, camera, size, *, sample_distance=None, window=None, clip_planes=None,
    cropping=None, component=None, matrix=None, interpolation="linear")``: sampled projections use
    ``sample_distance`` (samples at ``entry + k * sample_distance``), exact
    ones ignore it; ``clip_planes`` is ``(origins, normals)`` in world
    coordinates; ``cropping`` is ``(region planes, region flags)`` as VTK's
    ``SetCroppingRegionPlanes`` / ``GetCroppingRegionFlags()``; ``component`` as
    :meth:`~mipcast.MIPVolumeMapper.SetComponent`; ``matrix`` the volume's own
    (:func:`mipcast.reference.render`); ``interpolation`` ``"nearest"`` for the sampled ones under the
    volume property's nearest-neighbour interpolation.

    Examples
    --------
    >>> projection_reference("analytic_minip").__name__
    'analytic_minip_reference'
    """
    sampled = "sample_distance" in reference.METHODS[name]

    def projection(image, camera, size, *, sample_distance=None, window=None, clip_planes=None,
                   cropping=None, component=None, matrix=None, interpolation="linear") -> np.ndarray:
        extra = {"sample_distance": sample_distance} if sampled else {}
        return reference.render(image, camera, size, name, clip_planes=clip_planes, cropping=cropping,
                                component=component, matrix=matrix, interpolation=interpolation, **extra)

    projection.__name__ = f"{name}_reference"
    projection.__doc__ = f"The float64 reference of {name!r} (mipcast.reference.render)."
    return projection


sampled_mip_reference = projection_reference("mip")
exact_mip_reference = projection_reference("analytic")
sampled_minip_reference = projection_reference("minip")
exact_minip_reference = projection_reference("analytic_minip")
sampled_average_reference = projection_reference("average")
exact_average_reference = projection_reference("analytic_average")

#: Projection -> its exact float64 reference (the benchmark's errors are against these).
EXACT_REFERENCES = {"mip": exact_mip_reference, "minip": exact_minip_reference,
                    "average": exact_average_reference}
#: Projection -> its sampled float64 reference (the benchmark asks it which rays saw no finite sample).
SAMPLED_REFERENCES = {"mip": sampled_mip_reference, "minip": sampled_minip_reference,
                      "average": sampled_average_reference}


def demip_reference(image, camera, size, *, sample_distance: float, window, clip_planes=None,
                    cropping=None, **params) -> np.ndarray:
    """DEMIP's float readout (the ray's value) in float64."""
    return reference.render(image, camera, size, "demip", sample_distance=sample_distance,
                            window=window, output="value", clip_planes=clip_planes, cropping=cropping,
                            **params)


_DEMIP_BENCH = (
    ("demip", 1, ()),
    ("demip, no skipping", 1, (("Skipping", False),)),
    ("demip window depth", 1, (("DepthMode", "window"),)),
    ("demip steps depth", 1, (("DepthMode", "steps"),)),
    ("demip eye distance", 1, (("DepthMode", "eye_distance"),)),
    ("demip + sphere", 1, (("SphereWeight", 0.5),)),
)

#: Method name -> :class:`Method`, in the order front ends list them.
METHODS: Dict[str, Method] = {}


def register(method: Method) -> Method:
    """Add ``method`` to :data:`METHODS` (replacing one of the same name) and return it.

    A foveation layer also becomes a choice of the foveated method's
    ``method`` parameter.

    Examples
    --------
    >>> toy = Method("toy", "Toy", "the stock picture", _stock_mip, float_readout=False)
    >>> register(toy) is METHODS["toy"]
    True
    >>> unregister("toy")
    """
    METHODS[method.name] = method
    FOVEATION_LAYERS.pop(method.name, None)
    if method.foveation_layer:
        FOVEATION_LAYERS[method.name] = method
    return method


def unregister(name: str) -> None:
    """Remove a method added by :func:`register` (tests use it)."""
    METHODS.pop(name, None)
    FOVEATION_LAYERS.pop(name, None)


for _method in (
    Method("stock", "Stock VTK MIP", "VTK's own sampled GPU MIP (what users have today)", _stock_mip,
           reference=sampled_mip_reference, float_readout=False, readout_by="mip", rank_view="depth",
           bench=(("stock 1x", 1, ()), ("stock 2x", 2, ()), ("stock 4x", 4, ()), ("stock 8x", 8, ()))),
    Method("mip", "MIP", "sampled MIP through mipcast's own loop (samples at entry + k * step)",
           MIPVolumeMapper, reference=sampled_mip_reference, reference_tolerance=1e-4,
           parameters=parameter_tables.MIP, foveation_layer=True, distributed="max", bricks="max",
           bench=(("mip 1x", 1, ()), ("mip 1x, no skipping", 1, (("Skipping", False),)), ("auto", "auto", ()))),
    Method("analytic", "Analytic MIP", "the exact maximum of the trilinear interpolant, cell by cell",
           AnalyticMIPVolumeMapper, reference=exact_mip_reference, reference_tolerance=1e-4,
           parameters=parameter_tables.ANALYTIC, foveation_layer=True, walks_cells=True, distributed="max",
           bricks="max",
           bench=(("analytic", None, ()), ("analytic, no skipping", None, (("Skipping", False),)))),
    Method("demip", "DEMIP", "MIP brightened where its material is near (depth-enhanced MIP, colour sphere)",
           DEMIPVolumeMapper, reference=demip_reference, reference_tolerance=1e-4,
           parameters=parameter_tables.DEMIP, foveation_layer=True, distributed="demip", bricks="demip",
           bench=_DEMIP_BENCH),
    Method("demip_two_pass", "DEMIP (two passes)", "DEMIP split into two GPU passes, for timing the split",
           _demip_two_pass, reference=demip_reference, reference_tolerance=1e-4,
           parameters=parameter_tables.DEMIP_SETTINGS, distributed="demip", bricks="demip",
           bench=(("demip two passes", 1, ()),)),
    Method("foveated", "Foveated", "full quality around a gaze point, fewer rays and samples elsewhere",
           FoveatedVolumeMapper, parameters=parameter_tables.FOVEATED, bricks="foveated", rank_view="foveated",
           bench=(("foveated mip", 1, ()), ("foveated mip, gaze at a corner", 1, (("GazePoint", (0.1, 0.1)),)),
                  ("foveated analytic", None, (("Method", "analytic"),)))),
    Method("cpu", "VTK CPU MIP", "VTK's CPU ray caster (vtkFixedPointVolumeRayCastMapper), a peer",
           _cpu_mip, float_readout=False, in_view=True, bench=(("cpu 1x", 1, ()),)),
    Method("stock_minip", "Stock VTK MinIP", "VTK's own sampled GPU MinIP (MINIMUM_INTENSITY blend)", _stock_minip,
           reference=sampled_minip_reference, float_readout=False, readout_by="minip", projection="minip",
           rank_view="depth",
           bench=tuple((f"stock minip {n}x", n, ()) for n in (1, 2, 4, 8))),
    Method("minip", "MinIP", "sampled minimum intensity projection (stock's samples, mipcast's loop)",
           MinIPVolumeMapper, reference=sampled_minip_reference, reference_tolerance=1e-4,
           parameters=parameter_tables.MINIP, projection="minip", bricks="min",
           bench=tuple((f"minip {n}x", n, ()) for n in (1, 2, 4, 8)) + (("minip 1x, no skipping", 1,
                                                                      (("Skipping", False),)),)),
    Method("analytic_minip", "Analytic MinIP", "the exact minimum of the trilinear interpolant, cell by cell",
           AnalyticMinIPVolumeMapper, reference=exact_minip_reference, reference_tolerance=1e-4,
           parameters=parameter_tables.ANALYTIC, walks_cells=True, projection="minip", bricks="min",
           bench=(("analytic minip", None, ()), ("analytic minip, no skipping", None, (("Skipping", False),)))),
    Method("stock_average", "Stock VTK average", "VTK's own sampled GPU average (AVERAGE_INTENSITY blend)",
           _stock_average, reference=sampled_average_reference, float_readout=False, readout_by="average",
           projection="average", rank_view="mean", bench=tuple((f"stock average {n}x", n, ()) for n in (1, 2, 4, 8))),
    Method("average", "Average", "sampled average intensity projection (stock's samples and weighting)",
           AverageVolumeMapper, reference=sampled_average_reference, reference_tolerance=1e-4,
           parameters=parameter_tables.SAMPLED, projection="average", bricks="mean",
           bench=tuple((f"average {n}x", n, ()) for n in (1, 2, 4, 8))),
    Method("analytic_average", "Analytic average",
           "the exact mean of the trilinear interpolant along the ray (each cell's cubic integrated)",
           AnalyticAverageVolumeMapper, reference=exact_average_reference, reference_tolerance=1e-4,
           parameters=parameter_tables.ANALYTIC, walks_cells=True, projection="average", bricks="mean",
           bench=(("analytic average", None, ()),)),
):
    register(_method)


def create_mapper(method: str):
    """Create the mapper for ``method`` (one of :data:`METHODS`).

    Examples
    --------
    >>> type(create_mapper("mip")).__name__
    'MIPVolumeMapper'
    """
    return METHODS[check_choice("method", method, tuple(METHODS))].create()


def method_of(mapper) -> Optional[Method]:
    """The :class:`Method` whose factory made ``mapper`` (None if no entry matches its type).

    Examples
    --------
    >>> method_of(create_mapper("analytic")).name
    'analytic'
    """
    for method in METHODS.values():
        if isinstance(method.factory, type) and type(mapper) is method.factory:
            return method
    return None


def attach(mapper, volume) -> None:
    """Give ``volume`` its mapper: ``Attach`` for mipcast mappers, ``SetMapper`` for VTK's own.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> volume = vtkVolume()
    >>> mapper = create_mapper("stock")
    >>> attach(mapper, volume)
    >>> volume.GetMapper() is mapper
    True
    >>> attach(create_mapper("mip"), volume)
    >>> attach(create_mapper("stock"), volume)   # mipcast's pieces leave with the mipcast mapper
    >>> shader_pieces.installed_tags(volume.GetShaderProperty())
    []
    """
    if isinstance(mapper, MIPVolumeMapper):
        mapper.Attach(volume)
    else:  # VTK's own mapper: no mipcast piece may stay on the volume from a method drawn before
        shader_pieces.uninstall(volume.GetShaderProperty())
        volume.SetMapper(mapper)


def detach(mapper) -> None:
    """Undo :func:`attach`'s shader pieces (mipcast mappers; nothing for VTK's own)."""
    if isinstance(mapper, MIPVolumeMapper):
        mapper.Detach()

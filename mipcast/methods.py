"""The registry of rendering methods: a name -> a configured VTK volume mapper."""
from __future__ import annotations

from vtkmodules.vtkRenderingVolume import vtkFixedPointVolumeRayCastMapper
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast.mappers.analytic import AnalyticMIPVolumeMapper
from mipcast.mappers.demip import DEMIPVolumeMapper
from mipcast.mappers.demip_two_pass import DEMIPTwoPassVolumeMapper
from mipcast.mappers.foveated import FoveatedVolumeMapper
from mipcast.mappers.mip import MIPVolumeMapper
from mipcast.core.validation import check_choice


def _stock_mip() -> vtkOpenGLGPUVolumeRayCastMapper:
    mapper = vtkOpenGLGPUVolumeRayCastMapper()
    mapper.SetBlendModeToMaximumIntensity()
    return mapper


def _demip_two_pass() -> DEMIPTwoPassVolumeMapper:
    # a factory, not the class: foveation offers classes as layers
    # (foveated_mapper.layer_methods), and this comparison method's private
    # first pass would cast every ray at every level
    return DEMIPTwoPassVolumeMapper()


def _cpu_mip() -> vtkFixedPointVolumeRayCastMapper:
    mapper = vtkFixedPointVolumeRayCastMapper()
    mapper.SetBlendModeToMaximumIntensity()
    return mapper


#: Method name -> factory of an unconfigured mapper. "stock" is VTK's own GPU
#: MIP, "cpu" its CPU peer (vtkFixedPointVolumeRayCastMapper); neither has a
#: float readout. "foveated" renders one of the mipcast methods (default
#: "mip") gaze-directed: full quality around the gaze point only.
#: "demip_two_pass" is DEMIP split into two GPU passes (the paper's Table 2
#: comparison): the same picture as "demip", for timing the split.
METHODS = {
    "stock": _stock_mip,
    "cpu": _cpu_mip,
    "mip": MIPVolumeMapper,
    "analytic": AnalyticMIPVolumeMapper,
    "demip": DEMIPVolumeMapper,
    "demip_two_pass": _demip_two_pass,
    "foveated": FoveatedVolumeMapper,
}


def create_mapper(method: str):
    """Create the mapper for ``method`` (one of :data:`METHODS`).

    Examples
    --------
    >>> type(create_mapper("mip")).__name__
    'MIPVolumeMapper'
    """
    return METHODS[check_choice("method", method, tuple(METHODS))]()


def attach(mapper, volume) -> None:
    """Give ``volume`` its mapper: ``Attach`` for mipcast mappers, ``SetMapper`` for stock.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> volume = vtkVolume()
    >>> mapper = create_mapper("stock")
    >>> attach(mapper, volume)
    >>> volume.GetMapper() is mapper
    True
    """
    if hasattr(mapper, "Attach"):
        mapper.Attach(volume)
    else:
        volume.SetMapper(mapper)

"""mipcast: better maximum intensity projection in VTK's GPU volume ray caster.

The core imports VTK through ``vtkmodules`` only and pyvista lazily, so it
also runs inside ParaView's Python.

Examples
--------
>>> import mipcast
>>> sorted(mipcast.METHODS)  # doctest: +NORMALIZE_WHITESPACE
['analytic', 'analytic_average', 'analytic_minip', 'average', 'cpu', 'demip', 'demip_two_pass',
 'foveated', 'minip', 'mip', 'stock', 'stock_average', 'stock_minip']
"""
from mipcast.core.errors import InputError, InputWarning
from mipcast.mappers.analytic import AnalyticMIPVolumeMapper
from mipcast.mappers.demip import DEMIPVolumeMapper
from mipcast.mappers.demip_two_pass import DEMIPTwoPassVolumeMapper
from mipcast.mappers.foveated import FoveatedVolumeMapper
from mipcast.methods import METHODS, create_mapper
from mipcast.mappers.mip import MIPVolumeMapper
from mipcast.mappers.projections import (AnalyticAverageVolumeMapper, AnalyticMinIPVolumeMapper,
                                         AverageVolumeMapper, MinIPVolumeMapper)

__version__ = "0.1.0"
__all__ = ["METHODS", "InputError", "InputWarning", "AnalyticAverageVolumeMapper", "AnalyticMIPVolumeMapper",
           "AnalyticMinIPVolumeMapper", "AverageVolumeMapper", "DEMIPTwoPassVolumeMapper", "DEMIPVolumeMapper",
           "FoveatedVolumeMapper", "MIPVolumeMapper", "MinIPVolumeMapper", "create_mapper", "__version__"]

"""mipcast: better maximum intensity projection in VTK's GPU volume ray caster.

The core imports VTK through ``vtkmodules`` only and pyvista lazily, so it
also runs inside ParaView's Python.

Examples
--------
>>> import mipcast
>>> sorted(mipcast.METHODS)
['analytic', 'cpu', 'demip', 'demip_two_pass', 'foveated', 'mip', 'stock']
"""
from mipcast.core.errors import InputError, InputWarning
from mipcast.mappers.analytic import AnalyticMIPVolumeMapper
from mipcast.mappers.demip import DEMIPVolumeMapper
from mipcast.mappers.demip_two_pass import DEMIPTwoPassVolumeMapper
from mipcast.mappers.foveated import FoveatedVolumeMapper
from mipcast.methods import METHODS, create_mapper
from mipcast.mappers.mip import MIPVolumeMapper

__version__ = "0.1.0"
__all__ = ["METHODS", "InputError", "InputWarning", "AnalyticMIPVolumeMapper", "DEMIPTwoPassVolumeMapper", "DEMIPVolumeMapper",
           "FoveatedVolumeMapper", "MIPVolumeMapper", "create_mapper", "__version__"]

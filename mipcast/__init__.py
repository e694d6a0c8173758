"""mipcast: better maximum intensity projection in VTK's GPU volume ray caster.

The core imports VTK through ``vtkmodules`` only and pyvista lazily, so it
also runs inside ParaView's Python.

Examples
--------
>>> import mipcast
>>> sorted(mipcast.METHODS)
['analytic', 'cpu', 'demip', 'demip_two_pass', 'foveated', 'mip', 'stock']
"""
from .analytic_mapper import AnalyticMIPVolumeMapper
from .demip_mapper import DEMIPVolumeMapper
from .demip_two_pass import DEMIPTwoPassVolumeMapper
from .foveated_mapper import FoveatedVolumeMapper
from .methods import METHODS, create_mapper
from .mip_mapper import MIPVolumeMapper

__version__ = "0.1.0"
__all__ = ["METHODS", "AnalyticMIPVolumeMapper", "DEMIPTwoPassVolumeMapper", "DEMIPVolumeMapper",
           "FoveatedVolumeMapper", "MIPVolumeMapper", "create_mapper", "__version__"]

"""Volumes in: files (``.vti``, NRRD, NIfTI, MetaImage, DICOM) and arrays, checked for rendering.

Examples
--------
>>> from mipcast.io import SUPPORTED_EXTENSIONS
>>> ".vti" in SUPPORTED_EXTENSIONS
True
"""
from mipcast.io.volumes import SUPPORTED_EXTENSIONS, as_image_data, read_volume, right_handed, with_scalars

__all__ = ["SUPPORTED_EXTENSIONS", "as_image_data", "read_volume", "right_handed", "with_scalars"]

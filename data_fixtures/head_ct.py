"""A real head CT: ``Cranium.inv3`` from Debian's ``invesalius-examples``.

The file is GPL-2 and is fetched by apt, never committed.  An ``.inv3``
project is a gzipped tar holding ``main.plist`` (shape, dtype and spacing of
the volume) and ``matrix.dat`` (the raw voxels, little-endian, C order
``[slice, row, column]``).
"""
from __future__ import annotations

import functools
import os
import plistlib
import tarfile
import warnings
from pathlib import Path
from typing import Optional, Tuple, Union

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.data_fixtures.synthetic import image_from_array

ENV_VAR = "MIPCAST_HEAD_CT"
DEBIAN_PATHS = (Path("/usr/share/doc/invesalius-examples/examples/Cranium.inv3"),)


def head_ct_path() -> Optional[Path]:
    """Locate ``Cranium.inv3``.

    The file named by the environment variable ``MIPCAST_HEAD_CT`` wins if it
    exists (a warning is issued if it is set but missing); otherwise the path
    installed by ``apt-get install invesalius-examples``.

    Returns
    -------
    pathlib.Path or None
        The file, or ``None`` if it is not available (tests skip on ``None``).

    Examples
    --------
    >>> path = head_ct_path()
    >>> path is None or path.suffix == ".inv3"
    True
    """
    override = os.environ.get(ENV_VAR)
    if override:
        if Path(override).is_file():
            return Path(override)
        warnings.warn(f"{ENV_VAR}={override!r} is not a file; looking in the Debian paths",
                      stacklevel=2)
    return next((p for p in DEBIAN_PATHS if p.is_file()), None)


def load_head_ct(path: Union[str, Path, None] = None) -> vtkImageData:
    """Load the head CT as int16 Hounsfield units.

    Shape, dtype and spacing are read from the project's ``main.plist``.  For
    Debian's ``Cranium.inv3`` (InVesalius project "ProMED CT 0051") this gives
    256 x 256 x 108 points (x, y, z), spacing 0.957 x 0.957 x 1.5 mm and
    values -1024 to 2986 HU (dental fillings reach 2986).  Orientation, as
    seen in MIPs along each axis:

    - x (column): left-right; which side is the patient's left is not
      recorded in the file.
    - y (row): posterior to anterior -- the occiput and the curved head rest
      are at low y, the face and nose at high y.
    - z (slice): inferior to superior -- the maxilla and teeth (with metal)
      are at z = 0, the vertex near the last slice.

    The decoded array is cached per path; each call returns a fresh
    vtkImageData with its own copy of the voxels.

    Parameters
    ----------
    path : str or pathlib.Path, optional
        An ``.inv3`` file; default: :func:`head_ct_path`.

    Returns
    -------
    vtkImageData
        int16 point scalars named ``"HU"``, spacing from the file, origin 0.

    Raises
    ------
    FileNotFoundError
        If the file is absent (install it with
        ``apt-get install invesalius-examples``).
    ValueError
        If the project's metadata and voxel data disagree.
    
    Examples
    --------
    >>> if head_ct_path() is not None:  # apt-get install invesalius-examples
    ...     print(load_head_ct().GetDimensions())
    ... else:
    ...     print((256, 256, 108))
    (256, 256, 108)
    """
    path = head_ct_path() if path is None else Path(path)
    if path is None or not path.is_file():
        where = path if path is not None else " or ".join(map(str, DEBIAN_PATHS))
        raise FileNotFoundError(
            f"head CT not found at {where}: run 'apt-get install invesalius-examples' "
            f"or set {ENV_VAR} to a Cranium.inv3 file")
    voxels, spacing = _read_inv3(str(path.resolve()))
    return image_from_array(voxels, "HU", spacing)


@functools.lru_cache(maxsize=2)
def _read_inv3(path: str) -> Tuple[np.ndarray, Tuple[float, float, float]]:
    """Decode an ``.inv3`` file into a read-only ``[k, j, i]`` array and spacing."""
    with tarfile.open(path, "r:gz") as tar:
        members = {Path(m.name).name: m for m in tar.getmembers() if m.isfile()}
        if "main.plist" not in members:
            raise ValueError(f"{path} has no main.plist: not an InVesalius 3 project")
        meta = plistlib.loads(tar.extractfile(members["main.plist"]).read())
        matrix = meta["matrix"]
        raw = tar.extractfile(members[matrix["filename"]]).read()
    dtype = np.dtype(matrix["dtype"]).newbyteorder("<")
    shape = tuple(int(v) for v in matrix["shape"])
    if dtype != np.dtype("<i2"):
        raise ValueError(f"{path}: expected int16 Hounsfield units, main.plist says "
                         f"{matrix['dtype']}")
    if len(raw) != dtype.itemsize * int(np.prod(shape)):
        raise ValueError(f"{path}: {matrix['filename']} holds {len(raw)} bytes, but "
                         f"main.plist announces {matrix['dtype']} of shape {shape}")
    voxels = np.frombuffer(raw, dtype).reshape(shape).astype(np.int16)
    voxels.flags.writeable = False
    spacing = tuple(float(v) for v in meta["spacing"])
    return voxels, spacing

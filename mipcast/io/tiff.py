"""TIFF stacks as microscopes, Fiji and OME tools write them, read by tifffile.

A confocal, light-sheet or two-photon stack is a multi-page TIFF: ImageJ
hyperstacks (Fiji's *Save As > Tiff*), OME-TIFF (Bio-Formats, vendors'
exporters), or plain pages. tifffile, the reference TIFF reader in Python,
names each axis of the file's first series (``Z`` slices, ``C`` channels,
``T`` time points, ``S`` samples of an RGB pixel, ``I`` / ``Q`` pages of a
plain stack, ``Y`` rows, ``X`` columns) and decodes every compression
(LZW, Deflate, JPEG, ... through imagecodecs); :func:`read_tiff` makes the
volume of it:

* **Slices**: ``Z``, else the pages of a plain stack (``I``, ``Q``).
* **Spacing**: OME's ``PhysicalSizeX/Y/Z`` (in micrometres, converted from
  the file's units); ImageJ's ``XResolution`` / ``YResolution`` (pixels per
  unit) and its ``spacing`` (between slices), in its ``unit`` (micrometres
  when it names them); else 1 along that axis (a plain TIFF's resolution
  tags are a printer's, not a microscope's).
* **Components**: channels (``C``) or an RGB pixel's samples (``S``), drawn
  as their magnitude or one of them (``component``).
* **Volumes**: time points (``T``), of which ``volume`` is read (default the
  first, with a warning naming how many).
* **Placement**: as Fiji shows the stack: x to the right, the first row at
  the top, the first slice nearest a viewer looking down -z (mipcast's
  ``front`` view), so that the front view's analytic MIP is Fiji's *Z
  Project > Max Intensity* (the sampled methods take their first sample one
  step past the box's entry, VTK's rule: head-on, the first slice is not
  sampled). The direction matrix is ``diag(1, -1, -1)``: right-handed, the
  origin at the first row's first pixel of the first slice.
"""
from __future__ import annotations

import contextlib
import logging
import re
import struct
import warnings
from pathlib import Path
from typing import Optional

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.io.dicom import caller_level
from mipcast.io.volumes import volume_number, vtk_values

#: Micrometres in one of each length unit OME and ImageJ write (lower case; ImageJ's "micron", "\\u00B5m").
MICROMETRES = {"m": 1e6, "cm": 1e4, "mm": 1e3, "um": 1.0, "µm": 1.0, "μm": 1.0, "micron": 1.0, "microns": 1.0,
               "micrometer": 1.0, "micrometre": 1.0, "nm": 1e-3, "nanometer": 1e-3, "pm": 1e-6,
               "å": 1e-4, "angstrom": 1e-4}
#: Axes tifffile names that hold the slices of a stack, in order of preference.
SLICE_AXES = ("Z", "I", "Q")


def read_tiff(path: Path, volume: Optional[int] = None) -> vtkImageData:
    """The volume of a TIFF stack (its first series): see the module's description.

    Parameters
    ----------
    path : pathlib.Path
        A ``.tif`` / ``.tiff`` file (``.ome.tif`` too).
    volume : int, optional
        Which time point (``T``) to read, from 0; default the first, with a
        warning naming how many there are.

    Returns
    -------
    vtkImageData
        Point scalars ``"values"`` (the file's type; one component per
        channel or sample), spacing in micrometres when the file says so.

    Raises
    ------
    ValueError
        For a file tifffile cannot read, an axis mipcast cannot place
        (the message names the axes and what to do), or no ``volume`` of
        that number.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np, tifffile
    >>> path = Path(tempfile.mkdtemp()) / "stack.tif"
    >>> tifffile.imwrite(path, np.zeros((4, 8, 6), np.uint16), imagej=True, resolution=(5.0, 5.0),
    ...                  metadata={"spacing": 0.8, "unit": "micron", "axes": "ZYX"})
    >>> image = read_tiff(path)
    >>> image.GetDimensions(), tuple(round(s, 6) for s in image.GetSpacing())
    ((6, 8, 4), (0.2, 0.2, 0.8))
    """
    import tifffile

    with _tifffile_log() as log:
        try:
            tif = tifffile.TiffFile(str(path))
        except (tifffile.TiffFileError, OSError, ValueError, struct.error) as error:
            raise ValueError(f"cannot read '{path}' as TIFF: {_reason(error)}") from error
        with tif:
            if not tif.series or not tif.series[0].shape:
                raise ValueError(f"cannot read '{path}' as TIFF: it holds no image"
                                 + (f" (tifffile: {'; '.join(log)})" if log else ""))
            series = tif.series[0]
            values = _read_values(path, tif, series, series.axes.upper(), tuple(series.shape), volume, log)
            spacing = _spacing(tif)
    if log:  # read whole, but the file is damaged elsewhere (a page chain cut short)
        warnings.warn(f"'{path}' is damaged (tifffile: {'; '.join(log)}); the volume read is whole",
                      stacklevel=caller_level())
    return _image(values, spacing)


@contextlib.contextmanager
def _tifffile_log():
    """tifffile's logged complaints (a broken page chain, ...), kept off stderr: a list filled while inside."""
    messages = []

    class Collect(logging.Handler):
        def emit(self, record):
            messages.append(_reason(Exception(re.sub(r"<tifffile\.[^>]*>\s*", "", record.getMessage()))))

    logger = logging.getLogger("tifffile")
    handler, propagate = Collect(logging.WARNING), logger.propagate
    logger.addHandler(handler)
    logger.propagate = False
    try:
        yield messages
    finally:
        logger.removeHandler(handler)
        logger.propagate = propagate


def _decoded(path: Path, read, log: list):
    """``read()``, its failures (a damaged file, a codec not installed) as ValueError naming the file."""
    try:
        return read()
    except Exception as error:  # noqa: BLE001  (tifffile and its codecs raise many kinds)
        said = f"; tifffile: {'; '.join(log)}" if log else ""
        raise ValueError(f"cannot read '{path}' as TIFF: the file is damaged or incomplete, or compressed with a "
                         f"codec that is not installed ({_reason(error)}{said})") from error


def _read_values(path: Path, tif, series, axes: str, shape: tuple, volume: Optional[int], log: list) -> np.ndarray:
    """(z, y, x[, components]) values of time point ``volume``, only its pages decoded."""
    sizes = dict(zip(axes, shape))
    slices = next((axis for axis in SLICE_AXES if axis in sizes), None)
    if slices is None and sizes.get("S", 1) > 4 and sizes.get("C", 1) == 1:
        slices = "S"  # (tifffile's guess for a planar page of many samples: a stack of slices)
    placed = {"Y", "X", "C", "S", "T", slices}
    unknown = [f"{axis} ({sizes[axis]})" for axis in axes if axis not in placed and sizes[axis] > 1]
    stacked = [f"{axis} ({sizes[axis]})" for axis in SLICE_AXES if axis in sizes and axis != slices and sizes[axis] > 1]
    if unknown or stacked or "Y" not in sizes or "X" not in sizes:
        raise ValueError(
            f"cannot read '{path}': its axes are {axes} (sizes {' '.join(map(str, shape))}); mipcast reads rows Y, "
            "columns X, slices Z (or the pages of a plain stack), channels C or samples S as components and time "
            f"points T as volumes{'; ' + ', '.join(unknown + stacked) + ' cannot be placed' if unknown or stacked else ''}"
            ": save one volume per file (Fiji: Image > Duplicate, or Hyperstacks > Reduce Dimensionality)")
    if slices is None or sizes[slices] < 2:
        raise ValueError(
            f"cannot read '{path}': it holds one 2D image (axes {axes}, sizes {' '.join(map(str, shape))}), not a "
            "stack of slices; a projection needs at least 2 slices (a file of one slice per page, or an ImageJ "
            "hyperstack / OME-TIFF with a Z axis)")
    count = sizes.get("T", 1)
    time = volume_number(path, count, volume, ("time point", "time points"), "T")
    if "T" in sizes and count > 1:
        page_axes = axes[:len(axes) - _page_ndim(series)]
        values = _decoded(path, lambda: _time_point(tif, axes, shape, page_axes, time), log)
        axes = axes.replace("T", "")
    else:
        values = _decoded(path, series.asarray, log)
        if "T" in axes:
            values = np.take(values, 0, axis=axes.index("T"))
            axes = axes.replace("T", "")
    for axis in [a for a in axes if a not in ("Y", "X", "C", "S", slices)]:  # axes of size 1 left
        values = np.take(values, 0, axis=axes.index(axis))
        axes = axes.replace(axis, "")
    order = [axes.index(a) for a in (slices, "Y", "X")]
    components = [axes.index(a) for a in ("C", "S") if a in axes and a != slices]
    values = np.transpose(values, order + components)
    if values.ndim > 4:
        values = values.reshape(*values.shape[:3], -1)
    if values.dtype == bool:  # (bits: VTK's bit arrays are not drawn)
        values = values.astype(np.uint8)
    return vtk_values(values)  # half floats as float32, the machine's byte order, complex as two components


def _page_ndim(series) -> int:
    """How many trailing axes of ``series`` one page holds (Y X, or Y X S / S Y X)."""
    page = series.pages[0] if len(series.pages) else None
    return len(page.shape) if page is not None else 2


def _time_point(tif, axes: str, shape: tuple, page_axes: str, time: int) -> np.ndarray:
    """Time point ``time`` of a series of pages, decoding only its pages."""
    counts = shape[:len(page_axes)]
    grid = np.indices(counts).reshape(len(counts), -1)
    keep = grid[page_axes.index("T")] == time
    pages = np.ravel_multi_index(grid[:, keep], counts)
    values = tif.asarray(key=pages.tolist(), series=0)
    rest = tuple(size for axis, size in zip(axes, shape) if axis != "T")
    return values.reshape(rest)


def _spacing(tif) -> tuple:
    """(x, y, z) spacing: OME's physical sizes, else ImageJ's resolution and spacing, else 1."""
    if tif.is_ome and tif.ome_metadata:
        sizes = _ome_sizes(tif.ome_metadata)
        if sizes is not None:
            return sizes
    if tif.is_imagej and tif.imagej_metadata is not None:
        meta = tif.imagej_metadata
        scale = MICROMETRES.get(str(meta.get("unit", "")).strip().lower().replace("\\u00b5", "µ"), 1.0)
        page = tif.pages[0]
        x = _per_pixel(page.tags.get("XResolution"))
        y = _per_pixel(page.tags.get("YResolution"))
        z = meta.get("spacing")
        z = float(z) if isinstance(z, (int, float)) and np.isfinite(z) and z > 0 else None
        return tuple(scale * v if v is not None else 1.0 for v in (x, y, z))
    return (1.0, 1.0, 1.0)


def _per_pixel(tag) -> Optional[float]:
    """Units per pixel from a resolution tag (pixels per unit), or None when it says nothing."""
    if tag is None:
        return None
    value = tag.value
    pixels = value[0] / value[1] if isinstance(value, tuple) and len(value) == 2 and value[1] else value
    try:
        pixels = float(pixels)
    except (TypeError, ValueError):
        return None
    return 1.0 / pixels if np.isfinite(pixels) and pixels > 0 else None


def _ome_sizes(xml: str) -> Optional[tuple]:
    """(x, y, z) of the first image's ``PhysicalSize*`` in micrometres (1 where absent), or None if none."""
    import xml.etree.ElementTree as ElementTree

    try:
        root = ElementTree.fromstring(xml)
    except ElementTree.ParseError:
        return None
    pixels = next((element for element in root.iter() if element.tag.rsplit("}", 1)[-1] == "Pixels"), None)
    if pixels is None:
        return None
    sizes = []
    for axis in "XYZ":
        text = pixels.get(f"PhysicalSize{axis}")
        unit = pixels.get(f"PhysicalSize{axis}Unit", "µm").strip().lower()
        try:
            size = float(text) * MICROMETRES[unit] if text is not None else None
        except (ValueError, KeyError):
            size = None
        sizes.append(size if size is not None and np.isfinite(size) and size > 0 else None)
    if all(size is None for size in sizes):
        return None
    return tuple(size if size is not None else 1.0 for size in sizes)


def _image(values: np.ndarray, spacing: tuple) -> vtkImageData:
    """(z, y, x[, c]) values as image data placed as Fiji shows them (direction diag(1, -1, -1))."""
    nz, ny, nx = values.shape[:3]
    image = vtkImageData()
    image.SetDimensions(nx, ny, nz)
    image.SetSpacing(*spacing)
    image.SetDirectionMatrix(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0)
    points = np.ascontiguousarray(values)
    # (``points`` is tifffile's buffer or its contiguous copy: the VTK array keeps it alive, no second copy)
    array = numpy_to_vtk(points.reshape(nx * ny * nz, -1) if values.ndim == 4 else points.ravel(), deep=False)
    array.SetName("values")
    image.GetPointData().SetScalars(array)
    return image


def _reason(error: Exception) -> str:
    text = re.sub(r"\s+", " ", str(error)).strip() or type(error).__name__
    return text[:300]

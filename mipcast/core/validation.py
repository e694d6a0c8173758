"""Input checks shared by every mipcast entry point.

Each check raises a ``ValueError``/``TypeError`` whose message names the
problem and the fix.  Nothing passed in is modified.
"""
from __future__ import annotations

import math
from numbers import Real
from typing import Any

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData

SUPPORTED_DTYPES = (
    np.int8, np.uint8, np.int16, np.uint16, np.int32, np.uint32,
    np.float32, np.float64,
)


def check_image(image: Any) -> np.ndarray:
    """Validate a volume and return its scalars as a read-only (nz, ny, nx) view.

    Parameters
    ----------
    image : vtkImageData or pyvista.ImageData
        A volume with one-component point scalars.

    Returns
    -------
    numpy.ndarray, shape (nz, ny, nx)
        The active point scalars, indexed ``[k, j, i]`` (read-only view).

    Raises
    ------
    TypeError
        If ``image`` is not image data or the scalar type is unsupported.
    ValueError
        If the volume is empty or thinner than 2 points along an axis, has
        no point scalars, several components, NaN/Inf values, or 32/64-bit
        values whose offset is too large for float32 textures to resolve
        their range.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> check_image(make_fixture("spheres", size=16)).shape
    (16, 16, 16)
    """
    if not isinstance(image, vtkImageData):
        raise TypeError(
            f"expected vtkImageData or pyvista.ImageData, got {type(image).__name__}; "
            "convert the data set to image data first (e.g. vtkImageReslice or "
            "pyvista's sample/voxelize)")
    dims = image.GetDimensions()
    if image.GetNumberOfPoints() == 0:
        raise ValueError("the volume is empty (0 points); load or generate data first")
    if min(dims) < 2:
        raise ValueError(
            f"the volume has dimensions {dims}: at least 2 points are needed along "
            "every axis for a ray to cross a cell; pad the volume (e.g. repeat the "
            "slice) or use a 2D viewer")
    array = image.GetPointData().GetScalars()
    if array is None:
        if image.GetCellData().GetScalars() is not None:
            raise ValueError(
                "the volume has cell scalars but no point scalars; convert them with "
                "vtkCellDataToPointData (pyvista: image.cell_data_to_point_data())")
        raise ValueError(
            "the volume has no active point scalars; set one with "
            "image.GetPointData().SetActiveScalars(name) (pyvista: image.set_active_scalars)")
    if array.GetNumberOfComponents() != 1:
        raise ValueError(
            f"the scalars '{array.GetName()}' have {array.GetNumberOfComponents()} "
            "components; MIP needs one: extract a component or compute the magnitude "
            "first (e.g. vtkImageExtractComponents)")
    values = vtk_to_numpy(array)
    if values.dtype.type not in SUPPORTED_DTYPES:
        raise TypeError(
            f"scalar type {values.dtype} is not supported by the GPU ray caster; "
            "cast to float32, int16 or uint16 first (e.g. numpy .astype(np.float32))")
    if values.dtype.kind == "f" and not np.isfinite(values).all():
        bad = int(np.count_nonzero(~np.isfinite(values)))
        raise ValueError(
            f"the scalars contain {bad} NaN/Inf value(s); replace them first "
            "(e.g. numpy.nan_to_num with the data's minimum)")
    if values.dtype.itemsize >= 4 and values.dtype != np.float32:
        low, high = float(values.min()), float(values.max())
        # the GPU holds 32/64-bit data as float32: an offset this large hides the range
        if max(abs(low), abs(high)) * 2.0 ** -24 > (high - low) / 512.0:
            raise ValueError(
                f"the values span {low:g} to {high:g}: an offset this large relative to their "
                "range cannot be resolved by the GPU's float32 textures (the picture would be "
                "flat); subtract the offset first (e.g. values - values.min())")
    view = values.reshape(dims[2], dims[1], dims[0])
    view.flags.writeable = False
    return view


def check_positive(name: str, value: Any) -> float:
    """Return ``value`` as a finite float > 0, or raise naming ``name``.

    Examples
    --------
    >>> check_positive("sample_distance", 0.5)
    0.5
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(number) or number <= 0:
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return number


def check_finite(name: str, value: Any) -> float:
    """Return ``value`` as a finite float, or raise naming ``name``.

    Anything ``float()`` accepts is taken, as by :func:`check_positive`.

    Examples
    --------
    >>> check_finite("x", -2)
    -2.0
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(number):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return number


def check_non_negative(name: str, value: Any, *, numbers_only: bool = False) -> float:
    """Return ``value`` as a finite float >= 0, or raise naming ``name``.

    By default anything ``float()`` accepts is taken (as by
    :func:`check_finite`) and the messages say "must be a number", "must be
    finite" or "must be >= 0".  With ``numbers_only`` only real numbers are
    taken (not bool, not strings), as by :func:`check_unit`, and the
    messages say "must be a number >= 0" or "must be a finite number >= 0".

    Examples
    --------
    >>> check_non_negative("radius", "0.25")
    0.25
    >>> check_non_negative("attenuation", 0, numbers_only=True)
    0.0
    """
    if not numbers_only:
        number = check_finite(name, value)
        if number < 0:
            raise ValueError(f"{name} must be >= 0, got {value!r}")
        return number
    if not _is_number(value):
        raise TypeError(f"{name} must be a number >= 0, got {value!r}")
    number = float(value)
    if not (math.isfinite(number) and number >= 0.0):
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return number


def check_unit(name: str, value: Any, open_low: bool = False) -> float:
    """Return ``value`` as a float in [0, 1] ((0, 1] with ``open_low``), or raise naming ``name``.

    Only real numbers are taken (not bool, not strings).

    Examples
    --------
    >>> check_unit("depth_weight", 0.25)
    0.25
    >>> check_unit("material_threshold", 0.0, open_low=True)
    Traceback (most recent call last):
    ...
    ValueError: material_threshold must be in (0, 1], got 0.0
    """
    interval = "(0, 1]" if open_low else "[0, 1]"
    if not _is_number(value):
        raise TypeError(f"{name} must be a number in {interval}, got {value!r}")
    number = float(value)
    if not math.isfinite(number) or number > 1.0 or number < 0.0 or (open_low and number == 0.0):
        raise ValueError(f"{name} must be in {interval}, got {value!r}")
    return number


def _is_number(value: Any) -> bool:
    """Whether ``value`` is a real number (Python or numpy), not a bool."""
    return not isinstance(value, bool) and isinstance(value, (Real, np.number))


def check_choice(name: str, value: Any, choices: tuple) -> str:
    """Return ``value`` if it is one of ``choices``, else raise listing them.

    Examples
    --------
    >>> check_choice("method", "mip", ("mip", "exact"))
    'mip'
    """
    if value not in choices:
        raise ValueError(f"unknown {name} {value!r}; valid: {', '.join(map(repr, choices))}")
    return value


def check_size(size: Any) -> tuple:
    """Return a window size as ``(width, height)`` ints >= 1, or raise.

    Examples
    --------
    >>> check_size((64, 32))
    (64, 32)
    """
    try:
        width, height = (int(v) for v in size)
    except (TypeError, ValueError):
        raise TypeError(f"size must be (width, height), got {size!r}") from None
    if width < 1 or height < 1 or (width, height) != tuple(size):
        raise ValueError(f"size must be two integers >= 1, got {size!r}")
    return width, height

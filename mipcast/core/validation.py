"""Input checks shared by every mipcast entry point.

Each check raises a ``ValueError``/``TypeError`` whose message names the
problem and the fix.  Nothing passed in is modified.
"""
from __future__ import annotations

import math
from numbers import Real
from typing import Any, Optional, Tuple

import numpy as np

from mipcast.core.errors import InputError
from mipcast.core.prepare import CONVERTED_DTYPES, NATIVE_DTYPES, check_float_range, prepare_scalars

#: Scalar types mipcast draws (int64/uint64 through a float64 copy: see :mod:`mipcast.core.prepare`).
SUPPORTED_DTYPES = NATIVE_DTYPES + CONVERTED_DTYPES

__all__ = ["InputError", "check_image", "check_positive", "check_finite", "check_non_negative",
           "check_unit", "check_choice", "check_size", "SUPPORTED_DTYPES"]


def check_image(image: Any, component: Any = None, whole_range: Optional[Tuple[float, float]] = None) -> np.ndarray:
    """Validate a volume and return the values the GPU draws, read-only, shaped (nz, ny, nx).

    The values of :func:`mipcast.core.prepare.prepare_scalars`: the point
    scalars themselves (a view) for one-component data without NaN/Inf;
    otherwise a copy (the magnitude or ``component`` of multi-component
    scalars, NaN/Inf filled below the finite minimum, int64 as float64).

    Parameters
    ----------
    image : vtkImageData or pyvista.ImageData
        A volume with point scalars.
    component : int, "magnitude" or None
        Which component of multi-component scalars (default: the magnitude).
    whole_range : (low, high), optional
        The finite range of the whole volume ``image`` is a piece of (a
        rank's brick): its missing values are filled as the whole's, and it
        may hold missing values only.

    Returns
    -------
    numpy.ndarray, shape (nz, ny, nx)
        Indexed ``[k, j, i]`` (read-only).

    Raises
    ------
    TypeError
        If ``image`` is not image data or the scalar type is unsupported.
    InputError
        (a ``ValueError``) If the volume is empty or thinner than 2 points
        along an axis, has no point scalars, no finite value, a zero, negative
        or non-finite spacing, a direction matrix that is not orthonormal, or
        32/64-bit values whose offset is too large for float32 textures to
        resolve their range, or float values beyond float32's reach
        (:func:`mipcast.core.prepare.check_float_range`).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> check_image(make_fixture("spheres", size=16)).shape
    (16, 16, 16)
    """
    prepared = prepare_scalars(image, component, whole_range=whole_range)
    check_float_range(prepared, whole_range)
    return prepared.values


#: Voxel spacings from the origin beyond which the GPU's float32 ray set-up misplaces rays visibly (2**14: a
#: float32 coordinate there resolves 2**-10 of a spacing).  Measured on the 32³ vessel phantom against the float64
#: reference on the same rays (docs/reliability.md, *Coordinates far from the origin*).
FAR_FROM_ORIGIN = 2.0 ** 14

#: The most samples one ray may take. Mesa's llvmpipe ends a shader loop after 65536 iterations, so a ray
#: sampled more densely was cut short (the vessels 32³ at 2500 samples a voxel: 66 % of the range off the
#: float64 reference, stock VTK's MIP 63 %; tests/loop_limit_check.py), and a GPU's watchdog ends long draws.
MAX_SAMPLES_PER_RAY = 65536


def samples_per_ray_problem(image: Any, sample_distance: float) -> Optional[str]:
    """Why ``sample_distance`` is too fine for ``image`` (more than :data:`MAX_SAMPLES_PER_RAY` samples along
    the volume's diagonal, its longest ray), or None.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> samples_per_ray_problem(make_fixture("spheres", size=16), 0.1) is None
    True
    >>> samples_per_ray_problem(make_fixture("spheres", size=16), 1e-4)[:40]
    'sample distance 0.0001 takes 259808 samp'
    """
    # (math, not numpy: asked by every mipcast mapper before each render)
    diagonal = math.sqrt(sum(((max(n, 1) - 1) * s) ** 2 for n, s in zip(image.GetDimensions(), image.GetSpacing())))
    samples = diagonal / float(sample_distance) if sample_distance > 0 else math.inf
    if samples <= MAX_SAMPLES_PER_RAY:
        return None
    return (f"sample distance {sample_distance:g} takes {samples:.0f} samples along the volume's diagonal "
            f"({diagonal:g}); a ray takes at most {MAX_SAMPLES_PER_RAY} (llvmpipe ends longer shader loops, a GPU "
            f"times out long draws; a denser ray was cut short): use a sample distance of at least "
            f"{diagonal / MAX_SAMPLES_PER_RAY:.3g}, or an exact method (analytic, analytic_minip, analytic_average: "
            "no sample distance)")


def far_from_origin(image: Any) -> Optional[str]:
    """Why ``image``'s coordinates are too far from the origin for the GPU's float32 rays, or None.

    VTK's GPU ray caster (and mipcast's, built on it) takes the volume's
    corners and the camera in the image's own coordinates, origin included,
    as float32: beyond :data:`FAR_FROM_ORIGIN` voxel spacings from the origin
    (UTM coordinates, micrometres far from a stage origin) some rays start or
    point wrong.  The message names the fix: translate the volume first.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("spheres", size=8)
    >>> far_from_origin(image) is None
    True
    >>> image.SetOrigin(5.1e5, 4.2e6, 0.0)
    >>> print(far_from_origin(image))  # doctest: +ELLIPSIS
    the volume lies 4.2e+06 voxel spacings from the origin ...
    """
    bounds = np.abs(np.asarray(image.GetBounds(), dtype=np.float64))
    spacing = float(np.min(np.abs(image.GetSpacing())))
    if not spacing > 0.0 or not np.all(np.isfinite(bounds)):
        return None
    far = float(bounds.max()) / spacing
    if far <= FAR_FROM_ORIGIN:
        return None
    return (f"the volume lies {far:.2g} voxel spacings from the origin (bounds {tuple(image.GetBounds())}); the GPU "
            f"ray casters (VTK's and mipcast's) set rays up in float32, which resolves {far * 2.0 ** -24:.2g} of a "
            "spacing there, so some pixels are drawn wrong (a 32^3 phantom 2e4 spacings away: 0.06 % of the pixels "
            "up to 13 % of the range off; 1e6 away: 34 % of the pixels). Translate the volume near the origin "
            "first: image.SetOrigin(0, 0, 0) (pyvista: grid.origin = (0, 0, 0)), or subtract a reference point "
            "from its origin")


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

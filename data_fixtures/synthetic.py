"""Synthetic test volumes (phantoms) for MIP accuracy work.

Every fixture is a cube of ``size`` points, float32 point scalars named
``"scalars"`` with values in [0, 1], spacing 1 and origin 0, so index and
world coordinates agree.  Arrays are built in numpy as ``[k, j, i]``
(z, y, x) and are identical for identical ``(name, size, seed)``.
"""
from __future__ import annotations

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.validation import check_choice

FIXTURES = ("vessels", "spheres", "noise", "frontback", "airways")
MIN_SIZE, MAX_SIZE = 8, 512


def make_fixture(name: str, size: int = 64, seed: int = 0) -> vtkImageData:
    """Generate a synthetic volume by name.

    Parameters
    ----------
    name : str
        One of :data:`FIXTURES`:

        - ``"vessels"``: six thin straight tubes crossing the volume in seeded
          oblique directions (every direction component between 0.2 and 0.9
          in magnitude), radii 0.6-1.5 voxels, Gaussian cross-section
          ``exp(-d**2 / (2 r**2))`` with peak 1.0 on the centre line (the
          sampled maximum is lower where the line passes between points), on
          a background of uniform noise in [0.05, 0.15] plus a smooth
          variation of +-0.02.  Values in [0.03, 1].
        - ``"spheres"``: five balls of radius 1.5-4 voxels (at most
          ``size / 6``) with a one-voxel smoothstep edge and flat tops of
          intensities 1.0, 0.85, 0.7, 0.55 and 0.4, on a background of 0.
          They do not overlap or touch when ``size >= 32``.
        - ``"noise"``: white noise filtered (via FFT, periodically) with a
          Gaussian of sigma 2 voxels, rescaled to exactly [0, 1].
        - ``"frontback"``: two identical balls (radius ``0.1 * size``,
          flat top 1.0, smoothstep edge) on a background of 0.05.  The
          *low-z* ball is centred at ``(round(0.35 n), n // 2, round(0.25 n))``
          (x, y, z), the *high-z* ball at ``(round(0.65 n), n // 2,
          round(0.75 n))``, with ``n = size``.  Seen along z both are fully
          visible and their MIPs are identical: only depth tells them apart
          (the low-z ball is the front one for a camera on the -z side).
          ``seed`` is unused.
        - ``"airways"``: the MinIP phantom, air tubes in tissue: six thin
          straight tubes as in ``"vessels"`` (seeded oblique directions,
          radii 0.6-1.5 voxels) whose Gaussian cross-section dips from the
          tissue towards air, ``tissue * (1 - exp(-d**2 / (2 r**2)))``, in
          tissue of uniform noise in [0.75, 0.85] plus a smooth variation of
          +-0.02.  The air value 0 is reached on the centre lines only, so a
          sampled minimum misses much of each tube's depth where the line
          passes between points and samples.  Values in [0, 0.87].
    size : int, default: 64
        Number of points along each axis, 8 to 512.
    seed : int, default: 0
        Seed of the random generator (``numpy.random.default_rng``).

    Returns
    -------
    vtkImageData
        A ``size``-cubed volume with float32 point scalars ``"scalars"``.

    Raises
    ------
    ValueError
        For an unknown ``name`` (the message lists the valid ones) or a
        ``size`` outside [8, 512].
    TypeError
        If ``size`` is not an integer.

    Examples
    --------
    >>> image = make_fixture("spheres", size=32)
    >>> image.GetDimensions(), image.GetPointData().GetScalars().GetName()
    ((32, 32, 32), 'scalars')
    """
    check_choice("fixture", name, FIXTURES)
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)):
        raise TypeError(f"size must be an integer, got {size!r}")
    if not MIN_SIZE <= size <= MAX_SIZE:
        raise ValueError(f"size must be between {MIN_SIZE} and {MAX_SIZE}, got {size}")
    n = int(size)
    rng = np.random.default_rng(seed)
    array = _GENERATORS[name](n, rng)
    return image_from_array(array.astype(np.float32, copy=False), "scalars")


def _grid(n: int):
    """Broadcastable float32 index coordinates ``(z, y, x)``."""
    axis = np.arange(n, dtype=np.float32)
    return axis[:, None, None], axis[None, :, None], axis[None, None, :]


def _ball(n: int, center, radius: float) -> np.ndarray:
    """Flat-topped ball of value 1 with a one-voxel smoothstep edge."""
    z, y, x = _grid(n)
    cx, cy, cz = (float(c) for c in center)
    d = np.sqrt((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2)
    t = np.clip(radius + 0.5 - d, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def _vessels(n: int, rng: np.random.Generator) -> np.ndarray:
    volume = _background(n, rng, 0.05, 0.15)
    for tube in _tubes(n, rng):
        np.maximum(volume, tube, out=volume)
    return volume


def _airways(n: int, rng: np.random.Generator) -> np.ndarray:
    tissue = _background(n, rng, 0.75, 0.85)
    keep = np.ones_like(tissue)
    for tube in _tubes(n, rng):
        np.minimum(keep, np.float32(1.0) - tube, out=keep)
    return tissue * keep


def _background(n: int, rng: np.random.Generator, low: float, high: float) -> np.ndarray:
    """Uniform noise in [low, high] plus a smooth variation of +-0.02 (float32)."""
    z, y, x = _grid(n)
    phases = rng.uniform(0.0, 2.0 * np.pi, 3).astype(np.float32)
    smooth = sum(np.cos(2.0 * np.pi * c / n + p) for c, p in zip((x, y, z), phases))
    volume = rng.uniform(low, high, (n, n, n)).astype(np.float32)
    volume += np.float32(0.02 / 3.0) * smooth
    return volume


def _tubes(n: int, rng: np.random.Generator):
    """Six thin straight tubes in seeded oblique directions: Gaussian cross-sections, peak 1 (float32)."""
    z, y, x = _grid(n)
    for _ in range(6):
        direction = np.zeros(3)
        while not np.all((np.abs(direction) >= 0.2) & (np.abs(direction) <= 0.9)):
            direction = rng.normal(size=3)
            direction /= np.linalg.norm(direction)
        ux, uy, uz = direction.astype(np.float32)
        cx, cy, cz = (rng.uniform(0.3, 0.7, 3) * (n - 1)).astype(np.float32)
        scale = -0.5 / float(rng.uniform(0.6, 1.5)) ** 2  # python float: stays float32
        dx, dy, dz = x - cx, y - cy, z - cz
        along = dx * ux + dy * uy + dz * uz
        dist2 = np.maximum(dx * dx + dy * dy + dz * dz - along * along, 0.0)
        yield np.exp(dist2 * scale)


def _spheres(n: int, rng: np.random.Generator) -> np.ndarray:
    volume = np.zeros((n, n, n), np.float32)
    placed = []
    for intensity in (1.0, 0.85, 0.7, 0.55, 0.4):
        radius = rng.uniform(1.5, max(1.5, min(4.0, n / 6)))
        margin = radius + 1.0
        for _ in range(200):  # rejection sampling; overlap only if no room
            center = rng.uniform(margin, n - 1 - margin, 3)
            if all(np.linalg.norm(center - c) > radius + r + 2.0 for c, r in placed):
                break
        placed.append((center, radius))
        np.maximum(volume, np.float32(intensity) * _ball(n, center, radius), out=volume)
    return volume


def _noise(n: int, rng: np.random.Generator, sigma: float = 2.0) -> np.ndarray:
    white = rng.standard_normal((n, n, n))
    f2 = sum(np.meshgrid(np.fft.fftfreq(n) ** 2, np.fft.fftfreq(n) ** 2,
                         np.fft.rfftfreq(n) ** 2, indexing="ij", sparse=True))
    smooth = np.fft.irfftn(np.fft.rfftn(white) * np.exp(-2.0 * (np.pi * sigma) ** 2 * f2),
                           s=white.shape, axes=(0, 1, 2))
    smooth -= smooth.min()
    return smooth / smooth.max()


def _frontback(n: int, rng: np.random.Generator) -> np.ndarray:
    radius = 0.1 * n
    low = _ball(n, (round(0.35 * n), n // 2, round(0.25 * n)), radius)
    high = _ball(n, (round(0.65 * n), n // 2, round(0.75 * n)), radius)
    return np.maximum(np.maximum(low, high), np.float32(0.05))


_GENERATORS = {"vessels": _vessels, "spheres": _spheres, "noise": _noise,
               "frontback": _frontback, "airways": _airways}


def image_from_array(array: np.ndarray, name: str = "values", spacing=(1.0, 1.0, 1.0),
                     origin=(0.0, 0.0, 0.0), direction=None) -> vtkImageData:
    """Wrap a ``[k, j, i]`` array as vtkImageData point scalars (deep copy).

    Parameters
    ----------
    array : numpy.ndarray, shape (nz, ny, nx)
        Point values; the dtype is kept.
    name : str, default: "values"
        Name of the scalar array.
    spacing, origin : sequence of float
        Image geometry.
    direction : array_like, shape (3, 3), optional
        Direction matrix (default identity).

    Examples
    --------
    >>> image = image_from_array(np.zeros((2, 3, 4), np.float32), spacing=(1.0, 1.0, 2.5))
    >>> image.GetDimensions(), image.GetSpacing()
    ((4, 3, 2), (1.0, 1.0, 2.5))
    """
    image = vtkImageData()
    image.SetDimensions(array.shape[2], array.shape[1], array.shape[0])
    image.SetSpacing(*spacing)
    image.SetOrigin(*origin)
    if direction is not None:
        image.SetDirectionMatrix(*np.asarray(direction, dtype=float).ravel())
    scalars = numpy_to_vtk(np.ascontiguousarray(array).ravel(), deep=True)
    scalars.SetName(name)
    image.GetPointData().SetScalars(scalars)
    return image

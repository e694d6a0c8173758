"""DEMIP's shared definitions and maths: depth modes, colour sphere, chromadepth.

One place for what both the GPU mapper (:mod:`mipcast.mappers.demip`) and
the float64 reference (:mod:`mipcast.reference.demip`) mean by a depth mode,
a sphere colour or an orientation, and for the sphere colour the viewer's
legend draws.  numpy only.  See ``docs/methods.md`` (section DEMIP).
"""
from __future__ import annotations

import numpy as np

from mipcast.core.validation import check_choice

#: Depth measures of the paper (Fig. 3/4), in the order of ``u_mc_depthMode``.
DEPTH_MODES = ("window", "steps", "entry_plus_length", "eye_distance")

#: Colour sphere presets: name -> (front colour, back colour), RGB in [0, 1].
SPHERE_PRESETS = {
    "red-blue": ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    "green-red": ((0.0, 1.0, 0.0), (1.0, 0.0, 0.0)),
    "green-blue": ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
}

#: Ray projections: plain MIP (DEMIP's), local MIP, napari-style attenuated
#: MIP, and MIDA (the last two draw no DEMIP term).
PROJECTIONS = ("mip", "lmip", "attenuated", "mida")

#: Which sample gives the depth: DEMIP's first sample of the maximum's material,
#: or the (first) maximum itself (pseudo-chromadepth on plain MIP).
DEPTH_OF = ("same_material", "maximum")

#: Samples count as above the floor only beyond this fraction of the window
#: (far below one grey level): a background lying exactly at the floor must not
#: turn into "tissue" through float rounding of sample positions.
FLOOR_TOLERANCE = 1e-4

#: What the float readout (:func:`mipcast.mappers.float_readout.render_float`) reports.
READOUTS = ("value", "depth")

#: The identity rotation (the sphere's default orientation), as rows.
IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def rgb(name: str, value) -> tuple:
    try:
        rgb = tuple(float(c) for c in value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be an RGB triplet of numbers in [0, 1], got {value!r}") from None
    if len(rgb) != 3 or isinstance(value, str):
        raise TypeError(f"{name} must be an RGB triplet of numbers in [0, 1], got {value!r}")
    if not all(0.0 <= c <= 1.0 for c in rgb):
        raise ValueError(f"{name} must have components in [0, 1], got {value!r}")
    return rgb


def sphere_colors(colors: tuple) -> tuple:
    if len(colors) == 1 and isinstance(colors[0], str):
        return SPHERE_PRESETS[check_choice("sphere_colors", colors[0], tuple(SPHERE_PRESETS))]
    if len(colors) == 1 and not isinstance(colors[0], str):
        colors = tuple(colors[0]) if hasattr(colors[0], "__len__") else colors
    if len(colors) == 6 and not any(hasattr(c, "__len__") for c in colors):  # six numbers (command line)
        colors = (colors[:3], colors[3:])
    if len(colors) != 2:
        raise TypeError(f"sphere_colors must be a preset ({', '.join(map(repr, SPHERE_PRESETS))}) "
                        f"or two RGB triplets (front, back), got {colors!r}")
    return rgb("sphere_colors front colour", colors[0]), rgb("sphere_colors back colour", colors[1])


def rotation(rotation: tuple) -> tuple:
    """3 angles (degrees) or a 3x3 rotation matrix -> rows of the matrix."""
    if len(rotation) == 1:
        rotation = rotation[0]
    try:
        array = np.array(rotation, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError("sphere_orientation must be 3 angles in degrees or a 3x3 rotation "
                        f"matrix, got {rotation!r}") from None
    if array.shape == (3,):
        if not np.all(np.isfinite(array)):
            raise ValueError(f"sphere_orientation angles must be finite, got {rotation!r}")
        rx, ry, rz = np.radians(array)
        about_x = np.array([[1, 0, 0], [0, np.cos(rx), -np.sin(rx)], [0, np.sin(rx), np.cos(rx)]])
        about_y = np.array([[np.cos(ry), 0, np.sin(ry)], [0, 1, 0], [-np.sin(ry), 0, np.cos(ry)]])
        about_z = np.array([[np.cos(rz), -np.sin(rz), 0], [np.sin(rz), np.cos(rz), 0], [0, 0, 1]])
        array = about_z @ about_y @ about_x
    elif array.shape != (3, 3):
        raise TypeError("sphere_orientation must be 3 angles in degrees or a 3x3 rotation "
                        f"matrix, got shape {array.shape}")
    elif (not np.all(np.isfinite(array)) or np.abs(array.T @ array - np.eye(3)).max() > 1e-6
          or np.linalg.det(array) < 0):
        raise ValueError("sphere_orientation must be a rotation matrix (orthonormal, "
                         f"determinant +1), got {array.tolist()!r}")
    return tuple(tuple(float(v) for v in row) for row in array)


def sphere_color(directions: np.ndarray, axis, front, back) -> np.ndarray:
    """Colour-sphere colours (N, 3) of world ``directions`` (N, 3) from the box centre.

    ``mix(back, front, (1 + cos a) / 2)``, ``a`` the angle between ``axis``
    (the sphere's front pole) and the direction; a zero direction gets the
    mid colour.

    Examples
    --------
    >>> sphere_color(np.array([[0, 0, 2.0], [0, 0, -1.0], [0, 0, 0]]), (0, 0, 1), (1, 0, 0), (0, 0, 1)).tolist()
    [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.5, 0.0, 0.5]]
    """
    directions = np.asarray(directions, dtype=np.float64)
    front, back = np.asarray(front, dtype=np.float64), np.asarray(back, dtype=np.float64)
    size = np.linalg.norm(directions, axis=1)
    along = np.where(size > 0, (directions @ np.asarray(axis, dtype=np.float64)) / np.where(size > 0, size, 1.0), 0.0)
    return back + (front - back) * (0.5 + 0.5 * along)[:, None]


def chroma_color(depth: np.ndarray) -> np.ndarray:
    """Pseudo-chromadepth colours (N, 3): hue from red (depth 0) to blue (depth 1).

    Examples
    --------
    >>> chroma_color(np.array([0.0, 0.5, 1.0])).round(3).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    hue = 2.0 / 3.0 * np.asarray(depth, dtype=np.float64)[:, None]
    sextant = np.mod(hue + np.array([1.0, 2.0 / 3.0, 1.0 / 3.0]), 1.0) * 6.0
    return np.clip(np.abs(sextant - 3.0) - 1.0, 0.0, 1.0)

"""What the GPU draws from a user's volume: one component, missing values filled, a texture type.

:func:`prepare_scalars` is the single definition shared by the mappers (through
:class:`mipcast.mappers.input_preparer.InputPreparer`, inside the pipeline) and
the float64 references, so both compare like with like:

* **component**: one-component scalars are drawn as they are; several
  components are drawn as their magnitude (ParaView's default), or one chosen
  component (``component=k``).
* **missing values**: NaN and +-Inf voxels are *missing*.  They are filled
  with ``fill = low - span`` (``low``, ``high``: the finite range, ``span =
  high - low``, or ``max(|low|, 1)`` for a constant volume), below every
  finite value; the interpolant is the trilinear interpolant of the filled
  volume, and a ray whose result is below ``low`` (by more than
  :data:`MISSING_TOLERANCE` of the range: :attr:`PreparedScalars.missing_below`)
  saw no finite data: background, NaN in the float readout.  A finite
  maximum is therefore never a missing voxel, and a sample or cell touching
  a missing voxel is pulled down towards ``fill`` (never up).
* **hidden points and cells**: the points (cells) VTK's ghost array
  (``vtkGhostType``) marks HIDDENPOINT (HIDDENCELL), as blanking in a
  simulation's output or ``vtkImageData.BlankPoint`` writes them, and the
  points vtkProbeFilter's ``vtkValidPointMask`` marks 0, are missing too
  (:func:`hidden_points`); the copies drawn carry no ghost
  array (VTK's ray caster would hide them its own way).
* **cell data**: an image with cell scalars and no point scalars is drawn
  as the image of its cell centres (:func:`cell_centres`): the cell values
  are point values there, interpolated between the centres as VTK's GPU
  ray caster interpolates cell data.
* **types**: int8 ... uint32, float32 and float64 go to VTK as they are
  (VTK's textures hold 32/64-bit values as float32: exact up to 2**24), but
  int8 holding -128, which VTK's signed 8-bit texture reads as -127, goes
  as an int16 copy;
  int64/uint64, which VTK's GPU ray caster does not upload, are copied to
  float64 (then float32 on the GPU) and keep their data units.  A constant
  integer volume is drawn from a float32 copy (VTK's normalisation of a
  constant integer texture divides by zero).

See docs/reliability.md.

Examples
--------
>>> import numpy as np
>>> from vtkmodules.util.numpy_support import numpy_to_vtk
>>> from vtkmodules.vtkCommonCore import VTK_BIT
>>> from vtkmodules.vtkCommonDataModel import vtkDataSetAttributes, vtkImageData
>>> image = vtkImageData()
>>> image.SetDimensions(2, 2, 2)
>>> _ = image.GetPointData().SetScalars(numpy_to_vtk(np.array([0, 1, 2, 3, 4, 5, 6, np.nan]), deep=True))
>>> prepared = prepare_scalars(image)
>>> prepared.missing, prepared.low, prepared.high, float(prepared.values[1, 1, 1])
(1, 0.0, 6.0, -6.0)
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any, Optional, Tuple

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_BIT
from vtkmodules.vtkCommonDataModel import vtkDataSetAttributes, vtkImageData

from mipcast.core.errors import InputError

#: Scalar types VTK's GPU ray caster uploads as they are.
NATIVE_DTYPES = (np.int8, np.uint8, np.int16, np.uint16, np.int32, np.uint32, np.float32, np.float64)
#: Further types drawn through a float64 copy (VTK holds them, its GPU mapper does not upload them).
CONVERTED_DTYPES = (np.int64, np.uint64)
#: Ray results more than this fraction of the finite range below the finite
#: minimum saw no finite data (float32 rounding on the GPU stays inside it).
MISSING_TOLERANCE = 2.0 ** -20
#: Largest integer magnitude a float32 texture holds exactly.
FLOAT32_EXACT = 2 ** 24


@dataclass(frozen=True)
class PreparedScalars:
    """The one-component values the GPU draws (see the module docstring).

    Attributes
    ----------
    values : numpy.ndarray, shape (nz, ny, nx)
        Read-only; the user's own array (a view) when nothing had to change.
    changed : bool
        ``values`` is a copy (component, magnitude, fill or type changed).
    missing : int
        Number of NaN/+-Inf voxels (filled with ``fill``).
    infinite : int
        How many of them were +-Inf.
    low, high : float
        The finite range of the drawn values.
    fill : float
        The value missing voxels hold (``nan`` when none are missing).
    missing_below : float
        Ray results below this saw no finite data (``-inf`` when nothing is missing).
    component : str
        What is drawn: ``"scalars"``, ``"magnitude"`` or ``"component k"``.
    missing_above : float
        With ``fill_side="above"`` (minimum projections): ray results above
        this saw no finite data (``inf`` otherwise, and ``missing_below`` is
        then ``-inf``).
    cells : bool
        The values are the image's cell scalars, shaped and placed as the
        points of :func:`cell_centres` (:func:`scalar_image`), not of the image.
    """

    values: np.ndarray
    changed: bool
    missing: int
    infinite: int
    low: float
    high: float
    fill: float
    missing_below: float
    component: str
    missing_above: float = float("inf")
    cells: bool = False

    def seen(self, found: np.ndarray) -> np.ndarray:
        """Ray results ``found`` (data units) with those that saw no finite data NaN: below
        :attr:`missing_below` or above :attr:`missing_above` (background, NaN in the float readout).

        Examples
        --------
        >>> prepared = PreparedScalars(np.zeros((1, 1, 1)), True, 1, 0, 0.0, 6.0, -6.0, -6.0e-6, "scalars")
        >>> prepared.seen(np.array([-5.0, 0.5, np.nan])).tolist()
        [nan, 0.5, nan]
        """
        found = np.asarray(found, dtype=np.float64)
        return np.where((found < self.missing_below) | (found > self.missing_above), np.nan, found)


#: Where missing voxels are filled: below every finite value (maximum and
#: average projections) or above (minimum projections).
MISSING_SIDES = ("below", "above")


def shade_range(prepared, window=None) -> tuple:
    """The data range an average's grey is normalised over: the finite range.

    A constant volume has none: its grey is normalised over ``window`` (the
    transfer functions' range, as MIP draws a constant through its window),
    or over the value widened by 1 each way without one.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> shade_range(SimpleNamespace(low=2.0, high=5.0)), shade_range(SimpleNamespace(low=7.25, high=7.25))
    ((2.0, 5.0), (6.25, 8.25))
    >>> shade_range(SimpleNamespace(low=0.0, high=0.0), window=(0.2, 0.9))
    (0.2, 0.9)
    """
    low, high = float(prepared.low), float(prepared.high)
    if high > low:
        return low, high
    if window is not None and float(window[1]) > float(window[0]):
        return float(window[0]), float(window[1])
    return low - 1.0, high + 1.0


def check_component(component: Any) -> Optional[int]:
    """``None``/``"magnitude"``/-1 -> None (the default), or an int >= 0; else raise.

    Examples
    --------
    >>> check_component("magnitude") is None, check_component(2)
    (True, 2)
    """
    if component is None or (isinstance(component, str) and component.lower() == "magnitude"):
        return None
    if isinstance(component, bool) or not isinstance(component, (int, np.integer)):
        raise TypeError(f"component must be an int >= 0 or 'magnitude', got {component!r}")
    if component == -1:
        return None
    if component < 0:
        raise InputError(f"component must be >= 0 (or -1 / 'magnitude'), got {component!r}")
    return int(component)


def check_geometry(image: vtkImageData) -> None:
    """Refuse spacings and direction matrices the ray caster cannot draw (raise :class:`InputError`)."""
    spacing = image.GetSpacing()
    if not all(np.isfinite(s) and s != 0.0 for s in spacing):
        raise InputError(
            f"the volume's spacing {tuple(spacing)} has a zero or non-finite entry: rays cannot "
            "cross a cell of zero size; set a positive spacing (image.SetSpacing)")
    if min(spacing) < 0.0:
        raise InputError(
            f"the volume's spacing {tuple(spacing)} is negative: VTK's ray casters need positive "
            "spacing; use the absolute spacing and flip the axis with the direction matrix "
            "(image.SetDirectionMatrix; an odd number of flips then needs mipcast.io.right_handed) "
            "or the origin instead")
    direction = np.array([[image.GetDirectionMatrix().GetElement(r, c) for c in range(3)] for r in range(3)])
    if not np.all(np.isfinite(direction)) or np.abs(direction.T @ direction - np.eye(3)).max() > 1e-6:
        raise InputError(
            "the volume's direction matrix is not orthonormal (sheared or scaled axes): the GPU "
            "ray caster would draw it distorted; resample it onto an orthonormal grid "
            "(vtkImageReslice) or put the scale into the spacing")
    if np.linalg.det(direction) < 0:
        raise InputError(
            "the volume's direction matrix is a reflection (determinant -1, an odd number of flipped axes): "
            "VTK's GPU ray caster draws it wrong (its rays enter through the far faces: a nearly blank "
            "picture); reverse one axis of the data and negate its direction column, which keeps every "
            "voxel where it is: mipcast.io.right_handed(image) returns that copy (mipcast's pyvista filters "
            "and file readers do it themselves)")


def cell_centres(image: vtkImageData, name: Optional[str] = None) -> vtkImageData:
    """The image of ``image``'s cell centres, its cell arrays as point arrays (no value copied).

    A cell array of an image with dimensions (nx, ny, nz) is drawn as point
    data on the image of the cell centres: dimensions (nx-1, ny-1, nz-1)
    (extent one less at the top of each axis), the same spacing and
    direction, the origin moved by half a spacing along each axis of the
    direction matrix.  That is where VTK's GPU ray caster puts each cell's
    value (interpolated between the centres); the outer half cell, which VTK
    fills with the edge values, is outside this box.  The active scalars are
    the cell array ``name``, or the active cell scalars.  ``image`` is not
    modified; the arrays are shared.

    Raises
    ------
    InputError
        Fewer than 2 cells (3 points) along an axis, or no such cell array.

    Examples
    --------
    >>> import numpy as np
    >>> from vtkmodules.util.numpy_support import numpy_to_vtk
    >>> image = vtkImageData()
    >>> image.SetDimensions(4, 3, 3)
    >>> image.SetSpacing(2.0, 1.0, 1.0)
    >>> _ = image.GetCellData().SetScalars(numpy_to_vtk(np.arange(12.0)))
    >>> centres = cell_centres(image)
    >>> centres.GetDimensions(), centres.GetOrigin(), centres.GetPointData().GetScalars().GetValue(5)
    ((3, 2, 2), (1.0, 0.5, 0.5), 5.0)
    """
    cells = image.GetCellData()
    array = cells.GetScalars() if name is None else cells.GetArray(name)
    if array is None:
        raise InputError(f"the volume has no cell array {name!r}; cell arrays: "
                         f"{[cells.GetArrayName(i) for i in range(cells.GetNumberOfArrays())]}")
    dims = image.GetDimensions()
    if min(dims) < 3:
        raise InputError(
            f"the cell array '{array.GetName()}' of a volume with dimensions {dims} has fewer than 2 cells "
            "along an axis: cell values are drawn at the cell centres and interpolated between them, which "
            "needs at least 2 cells (3 points) along every axis; convert it to point data "
            "(vtkCellDataToPointData; pyvista: image.cell_data_to_point_data()) or pad the volume")
    spacing = np.array(image.GetSpacing())
    direction = np.array([[image.GetDirectionMatrix().GetElement(r, c) for c in range(3)] for r in range(3)])
    extent = list(image.GetExtent())
    out = vtkImageData()
    out.SetExtent(extent[0], extent[1] - 1, extent[2], extent[3] - 1, extent[4], extent[5] - 1)
    out.SetSpacing(*spacing)
    out.SetDirectionMatrix(image.GetDirectionMatrix())
    out.SetOrigin(*(np.array(image.GetOrigin()) + direction @ (0.5 * spacing)))
    points = out.GetPointData()
    points.ShallowCopy(cells)
    ghosts = cells.GetArray(vtkDataSetAttributes.GhostArrayName())
    if ghosts is not None:  # cell ghost bits -> the centres' point ghost bits
        flags = vtk_to_numpy(ghosts).astype(np.int64)
        translated = np.where(flags & vtkDataSetAttributes.HIDDENCELL, vtkDataSetAttributes.HIDDENPOINT, 0) | \
            np.where(flags & vtkDataSetAttributes.DUPLICATECELL, vtkDataSetAttributes.DUPLICATEPOINT, 0)
        points.RemoveArray(vtkDataSetAttributes.GhostArrayName())
        point_ghosts = numpy_to_vtk(translated.astype(np.uint8), deep=True)
        point_ghosts.SetName(vtkDataSetAttributes.GhostArrayName())
        points.AddArray(point_ghosts)
    address = array.GetAddressAsString("vtkObjectBase")  # by object: the array may have no name
    points.SetActiveAttribute(next(i for i in range(points.GetNumberOfArrays()) if points.GetAbstractArray(i)
                                   .GetAddressAsString("vtkObjectBase") == address), points.SCALARS)
    return out


#: The point array vtkProbeFilter (and ParaView's Resample With Dataset) writes: 0 where no source cell held
#: the point.
VALID_POINT_MASK = "vtkValidPointMask"


def hidden_points(image: vtkImageData) -> Optional[np.ndarray]:
    """Which points hold no data, or None when none does: the HIDDENPOINT bit of the image's point ghost
    array, or 0 in its :data:`VALID_POINT_MASK` array.

    The image of cell centres (:func:`cell_centres`) carries its cells' HIDDENCELL bits as HIDDENPOINT.

    Examples
    --------
    >>> image = vtkImageData()
    >>> image.SetDimensions(2, 2, 2)
    >>> image.AllocateScalars(10, 1)  # float
    >>> image.BlankPoint(3)
    >>> np.flatnonzero(hidden_points(image)).tolist()
    [3]
    """
    data = image.GetPointData()
    ghosts, valid = data.GetArray(vtkDataSetAttributes.GhostArrayName()), data.GetArray(VALID_POINT_MASK)
    hidden = None  # (neither array: nothing allocated, as for most volumes)
    if ghosts is not None:
        hidden = (vtk_to_numpy(ghosts).astype(np.int64) & vtkDataSetAttributes.HIDDENPOINT) != 0
    if valid is not None and valid.GetNumberOfComponents() == 1:
        invalid = vtk_to_numpy(valid) == 0
        hidden = invalid if hidden is None else hidden | invalid
    return hidden if hidden is not None and hidden.any() else None


def scalar_image(image: Any) -> Any:
    """The image whose point scalars are drawn: ``image``, or :func:`cell_centres` of an image that has
    cell scalars and no point scalars (anything else is returned as it is).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> points = make_fixture("spheres", size=8)
    >>> scalar_image(points) is points, scalar_image(None) is None   # a cell image: see cell_centres
    (True, True)
    """
    if isinstance(image, vtkImageData) and image.GetPointData().GetScalars() is None \
            and image.GetCellData().GetScalars() is not None and image.GetNumberOfPoints() > 0:
        return cell_centres(image)
    return image


#: The float values the GPU draws right, (largest magnitude, smallest range) per type (measured:
#: docs/reliability.md, "Scalar types"). float32 reaches the shaders raw, where sums and differences of
#: values past 2^123 overflow and ranges below 2^-110 meet float32's subnormals (flushed to zero); float64
#: is normalised by VTK before its float32 texture, so float32's largest value and, for VTK's own average,
#: ranges below 2^-120 bind.
FLOAT_LIMITS = {"float32": (2.0 ** 123, 2.0 ** -110), "float64": (float(np.finfo(np.float32).max), 2.0 ** -120)}


def check_float_range(prepared: "PreparedScalars", whole_range: Optional[Tuple[float, float]] = None) -> None:
    """Refuse float values beyond what the GPU's float32 textures and shaders hold (:data:`FLOAT_LIMITS`;
    every method drew garbage: a float64 volume of energies in erg, 1e50, or of 1e-40s; float32 past 1e37
    or with a range of 1e-35). Checked on the user's data (:func:`mipcast.core.validation.check_image`, the
    mappers' :class:`~mipcast.mappers.input_preparer.InputPreparer`), over ``whole_range`` on a rank's piece.

    Raises
    ------
    InputError
        Naming the range, the limit and the fix (a scale to apply first).
    """
    dtype = prepared.values.dtype
    if dtype.kind != "f":
        return
    low, high = (float(v) for v in whole_range) if whole_range is not None else (prepared.low, prepared.high)
    largest, smallest = FLOAT_LIMITS["float32" if dtype == np.float32 else "float64"]
    reach = max(abs(low), abs(high))
    if reach > largest:
        scale = 10.0 ** np.floor(np.log10(reach) - 3)
        raise InputError(
            f"the values span {low:g} to {high:g}, beyond {largest:.3g}, the most the GPU's float32 textures "
            f"and shaders hold for {dtype.name} data (they would overflow); scale them first (e.g. values / "
            f"{scale:.0e}) or draw their logarithm")
    if 0.0 < high - low < smallest:
        scale = 10.0 ** np.floor(-np.log10(high - low))
        raise InputError(
            f"the values span {low:g} to {high:g}: a range below {smallest:.3g} is lost in the GPU's float32 "
            f"textures and shaders for {dtype.name} data (flushed to zero or rounded away there); scale them "
            f"first (e.g. values * {scale:.0e})")


def missing_fill(low: float, high: float, fill_side: str = "below", dtype=np.float64) -> Tuple[float, float, float]:
    """(fill, missing_below, missing_above) of a volume with missing values whose finite range is ``low, high``.

    What :func:`prepare_scalars` fills missing voxels with (``low - span``
    below, ``high + span`` above, in ``dtype``) and the thresholds beyond
    which a ray result saw no finite data (:meth:`PreparedScalars.seen`);
    the pieces of a volume spread over ranks or bricks agree on them from
    the whole volume's finite range alone.

    Examples
    --------
    >>> missing_fill(2.0, 6.0)[:2], missing_fill(2.0, 6.0, "above")[0]
    ((-2.0, 1.9999961853027344), 10.0)
    """
    span = high - low if high > low else max(abs(low), 1.0)
    if fill_side == "below":
        return float(np.asarray(low - span, dtype=dtype)), low - MISSING_TOLERANCE * span, float("inf")
    return float(np.asarray(high + span, dtype=dtype)), float("-inf"), high + MISSING_TOLERANCE * span


def prepare_scalars(image: vtkImageData, component: Any = None, fill_side: str = "below",
                    whole_range: Optional[Tuple[float, float]] = None) -> PreparedScalars:
    """The values the GPU draws from ``image`` (validated; ``image`` is not modified).

    Parameters
    ----------
    image : vtkImageData or pyvista.ImageData
    component : int, "magnitude" or None
        Which component of multi-component scalars; None: the magnitude
        (one-component scalars are drawn as they are either way, unless
        ``component`` is >= 1).
    fill_side : {"below", "above"}
        Fill missing voxels below every finite value (``low - span``: maximum
        and average projections) or above (``high + span``: minimum projections).
    whole_range : (low, high), optional
        ``image`` is a piece of a larger volume (an MPI rank's piece) whose
        finite range this is: the fill and the missing thresholds are the
        whole volume's (``low``, ``high`` and ``span`` of this range), so a
        sample near a missing voxel takes the value it has in the whole
        volume, on every piece; a piece holding only missing values is then
        filled entirely (it draws nothing).  ``low`` and ``high`` of the
        result stay the piece's own finite range.

    Raises
    ------
    TypeError
        Not image data, or an unsupported scalar type.
    InputError
        Empty, thinner than 2 points (cell scalars: 2 cells), no scalars, no finite value,
        a component out of range, bad spacing or direction, or 32/64-bit values
        whose offset float32 textures cannot resolve.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> prepare_scalars(make_fixture("spheres", size=8)).changed
    False
    >>> import numpy as np
    >>> from vtkmodules.util.numpy_support import numpy_to_vtk
    >>> piece = vtkImageData()
    >>> piece.SetDimensions(2, 2, 2)
    >>> _ = piece.GetPointData().SetScalars(numpy_to_vtk(np.array([0, 1, 2, 3, 4, 5, 6, np.nan]), deep=True))
    >>> prepare_scalars(piece).fill, prepare_scalars(piece, whole_range=(-2.0, 8.0)).fill
    (-6.0, -12.0)
    """
    if fill_side not in MISSING_SIDES:
        raise ValueError(f"fill_side must be one of {MISSING_SIDES}, got {fill_side!r}")
    if not isinstance(image, vtkImageData):
        raise TypeError(
            f"expected vtkImageData or pyvista.ImageData, got {type(image).__name__}; "
            "convert the data set to image data first (e.g. vtkImageReslice or "
            "pyvista's sample/voxelize)")
    if image.GetNumberOfPoints() == 0:
        raise InputError("the volume is empty (0 points); load or generate data first")
    drawn = scalar_image(image)
    cells, image = drawn is not image, drawn
    hidden = hidden_points(image)
    dims = image.GetDimensions()
    if min(dims) < 2:
        raise InputError(
            f"the volume has dimensions {dims}: at least 2 points are needed along "
            "every axis for a ray to cross a cell; pad the volume (e.g. repeat the "
            "slice) or use a 2D viewer")
    array = image.GetPointData().GetScalars()
    if array is None:
        raise InputError(
            "the volume has no active point scalars (nor cell scalars); set one with "
            "image.GetPointData().SetActiveScalars(name) (pyvista: image.set_active_scalars)")
    check_geometry(image)
    chosen = check_component(component)
    if array.GetDataType() == VTK_BIT:
        raise TypeError(
            f"the scalars '{array.GetName()}' are a bit array, which the GPU ray caster cannot "
            "upload; convert them to uint8 first (e.g. vtkImageCast)")
    try:
        raw = np.asarray(vtk_to_numpy(array))
    except Exception:  # VTK 9.7's vtk_to_numpy fails on implicit arrays with a NameError of its own
        raise TypeError(
            f"the scalars '{array.GetName()}' are a {re.sub(r'^[0-9]+', '', array.GetClassName())}, whose values "
            "are computed, not stored (an implicit array), which neither numpy nor the GPU ray caster reads "
            "directly; copy them into a plain array first (e.g. copy = vtkDoubleArray(); "
            "copy.DeepCopy(array))") from None
    if raw.dtype not in NATIVE_DTYPES + CONVERTED_DTYPES:  # (dtype equality: numpy's longlong is int64 too)
        raise TypeError(
            f"scalar type {raw.dtype} is not supported by the GPU ray caster; "
            "cast to float32, int16 or uint16 first (e.g. numpy .astype(np.float32))")
    components = array.GetNumberOfComponents()
    raw = raw.reshape(-1, components)
    changed = False
    if chosen is not None and chosen >= components:
        raise InputError(
            f"component {chosen} was asked for, but the scalars '{array.GetName()}' have "
            f"{components} component(s): choose 0 .. {components - 1} or 'magnitude'")
    if components == 1:
        values, what = raw[:, 0], "scalars"
    elif chosen is None:
        with np.errstate(over="ignore", invalid="ignore"):
            values = np.sqrt(np.sum(np.square(raw.astype(np.float64)), axis=1))
        values = values.astype(np.float32) if raw.dtype == np.float32 else values
        what, changed = "magnitude", True
    else:
        values, what, changed = np.ascontiguousarray(raw[:, chosen]), f"component {chosen}", True
    if values.dtype in CONVERTED_DTYPES:
        values, changed = values.astype(np.float64), True
    if hidden is not None:
        if values.dtype.kind != "f":  # float32 holds 8/16-bit integers exactly
            values = values.astype(np.float32 if values.dtype.itemsize <= 2 else np.float64)
        values, changed = np.where(hidden, values.dtype.type(np.nan), values), True
    missing = infinite = 0
    fill, missing_below, missing_above = float("nan"), float("-inf"), float("inf")
    if values.dtype.kind == "f":
        finite = np.isfinite(values)
        missing = int(values.size - np.count_nonzero(finite))
        if missing:
            infinite = int(np.count_nonzero(np.isinf(values)))
            if missing == values.size and whole_range is None:
                raise InputError(
                    f"all {missing} values of '{array.GetName()}' are NaN/Inf or hidden (missing): there is "
                    "nothing to draw; check the data or choose another array")
            wlow, whigh = (float(v) for v in whole_range) if whole_range is not None else (
                float(values[finite].min()), float(values[finite].max()))
            low, high = (float(values[finite].min()), float(values[finite].max())) if missing < values.size \
                else (wlow, whigh)
            fill, missing_below, missing_above = missing_fill(wlow, whigh, fill_side, values.dtype)
            values, changed = np.where(finite, values, values.dtype.type(fill)), True
    low, high = (float(values.min()), float(values.max())) if not missing else (low, high)
    if values.dtype == np.int8 and low == -128:
        # VTK's signed 8-bit texture holds -128 as -127 (signed normalised texels clamp at -1): an int16 copy
        values, changed = values.astype(np.int16), True
    if values.dtype.kind in "iu" and low == high:
        # VTK's normalisation of a constant integer texture divides by zero: draw it as float32
        values, changed = values.astype(np.float32), True
    if values.dtype.itemsize >= 4 and values.dtype != np.float32:
        # the GPU holds 32/64-bit data as float32: an offset this large hides the range
        if max(abs(low), abs(high)) * 2.0 ** -24 > (high - low) / 512.0 and high > low:
            raise InputError(
                f"the values span {low:g} to {high:g}: an offset this large relative to their "
                "range cannot be resolved by the GPU's float32 textures (the picture would be "
                "flat); subtract the offset first (e.g. values - values.min())")
    view = values.reshape(dims[2], dims[1], dims[0])
    view.flags.writeable = False
    return PreparedScalars(view, changed, missing, infinite, low, high, fill, missing_below, what, missing_above,
                           cells)

"""Pipeline filter between the user's image and VTK: the values :func:`prepare_scalars` defines.

Every mipcast mapper feeds VTK through its own :class:`InputPreparer`, so
``GetInput()`` still returns the user's image (never modified) while the GPU
draws one component with missing values filled (see
:mod:`mipcast.core.prepare`).  Valid finite one-component input passes
through as it is (a shallow copy: the same array, the same texture).
"""
from __future__ import annotations

import warnings
from typing import Optional

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonDataModel import vtkDataSetAttributes, vtkImageData

from mipcast.core.errors import InputError, InputWarning
from mipcast.core.prepare import (VALID_POINT_MASK, PreparedScalars, check_component, check_float_range, prepare_scalars,
                                  scalar_image, shade_range)
from mipcast.core.validation import far_from_origin


#: Arrays (address, modification time) already warned about.
_WARNED: set = set()


class InputPreparer(VTKPythonAlgorithmBase):
    """vtkImageData in, the drawn one-component values out (geometry copied).

    Input that cannot be drawn gives a 2x2x2 float zero volume (so shaders
    still compile) and :meth:`GetProblem` says why; the mapper refuses to
    draw it.  +-Inf values (drawn as missing) give one
    :class:`mipcast.InputWarning` per volume, not per frame.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> preparer = InputPreparer()
    >>> image = make_fixture("spheres", size=8)
    >>> preparer.SetInputDataObject(image)
    >>> _ = preparer.Update()
    >>> out = preparer.GetOutputDataObject(0)
    >>> out.GetPointData().GetScalars() is image.GetPointData().GetScalars(), preparer.GetProblem()
    (True, None)
    """

    def __init__(self, fill_side: str = "below") -> None:
        super().__init__(nInputPorts=1, inputType="vtkImageData", nOutputPorts=1, outputType="vtkImageData")
        self._fill_side = fill_side  # missing voxels below (MIP, average) or above (MinIP) the data
        self._component: Optional[int] = None
        self._problem: Optional[str] = None
        self._prepared: Optional[PreparedScalars] = None
        self._whole_range: Optional[tuple] = None
        self._mask: Optional[vtkImageData] = None
        self._mask_stamp: Optional[tuple] = None
        self._masked: Optional[vtkImageData] = None

    def SetComponent(self, component) -> None:
        """Component of multi-component scalars to draw (int >= 0), or -1 / None / "magnitude"."""
        component = check_component(component)
        if component != self._component:
            self._component = component
            self.Modified()

    def GetComponent(self) -> int:
        """The drawn component, -1 for the magnitude (the default)."""
        return -1 if self._component is None else self._component

    def SetWholeRange(self, whole_range) -> None:
        """The finite (low, high) of the whole volume the input is a piece of (an MPI rank's), or None.

        Missing values are then filled relative to it, as in the whole volume
        (:func:`~mipcast.core.prepare.prepare_scalars`' ``whole_range``).

        Examples
        --------
        >>> import numpy as np
        >>> from vtkmodules.util.numpy_support import numpy_to_vtk
        >>> piece = vtkImageData()
        >>> piece.SetDimensions(2, 2, 2)
        >>> _ = piece.GetPointData().SetScalars(numpy_to_vtk(np.array([0, 1, 2, 3, 4, 5, 6, np.nan]), deep=True))
        >>> preparer = InputPreparer()
        >>> preparer.SetInputDataObject(piece)
        >>> preparer.SetWholeRange((-4.0, 6.0))
        >>> _ = preparer.Update()
        >>> preparer.GetPrepared().fill, preparer.GetPrepared().low   # the whole's fill, the piece's own range
        (-14.0, 0.0)
        """
        whole_range = None if whole_range is None else (float(whole_range[0]), float(whole_range[1]))
        if whole_range != self._whole_range:
            self._whole_range = whole_range
            self.Modified()

    def GetWholeRange(self) -> Optional[tuple]:
        """What :meth:`SetWholeRange` set (None: the input is the whole volume)."""
        return self._whole_range

    def SetMask(self, mask: Optional[vtkImageData]) -> None:
        """A binary mask, or None: points where its scalars are 0 or less are missing data (:func:`masked`).

        The mapper's ``SetMaskInput`` sets it, and sets it again before each
        update: a mask modified since is read again (its modification time).
        """
        stamp = None if mask is None else (mask.GetAddressAsString("vtkObjectBase"), mask.GetMTime())
        if stamp != self._mask_stamp:
            self._mask, self._mask_stamp = mask, stamp
            self.Modified()

    def GetMasked(self) -> Optional[vtkImageData]:
        """The last input with the mask's hidden points (:func:`masked`), or None without a mask (or refused).

        What the foveated pyramid and the bricks cut from, so that a mask is
        applied once per input and mask.
        """
        return self._masked

    def GetProblem(self) -> Optional[str]:
        """Why the last input cannot be drawn, or None."""
        return self._problem

    def GetPrepared(self) -> Optional[PreparedScalars]:
        """What the last run prepared (None if the input was refused)."""
        return self._prepared

    def RequestData(self, request, in_info, out_info) -> int:
        source = vtkImageData.GetData(in_info[0])
        target = vtkImageData.GetData(out_info)
        self._masked = None
        try:
            if self._mask is not None:
                source = self._masked = masked(source, self._mask)
            prepared = prepare_scalars(source, self._component, self._fill_side, self._whole_range)
            check_float_range(prepared, self._whole_range)
        except (TypeError, InputError) as error:
            self._problem, self._prepared = str(error), None
            target.SetDimensions(2, 2, 2)
            target.GetPointData().SetScalars(numpy_to_vtk(np.zeros(8, np.float32), deep=True))
            return 1
        self._problem, self._prepared = None, prepared
        warn_if_far_from_origin(source)
        if prepared.cells:  # drawn on the image of the cell centres (mipcast.core.prepare.cell_centres)
            source = scalar_image(source)
        if not prepared.changed:
            target.ShallowCopy(source)
            return 1
        stamp = (source.GetPointData().GetScalars().GetAddressAsString("vtkObjectBase"),
                 source.GetPointData().GetScalars().GetMTime())
        if prepared.infinite and stamp not in _WARNED:  # once per volume, even with several mappers
            _WARNED.add(stamp)
            warnings.warn(
                f"{prepared.infinite} +-Inf value(s) in '{source.GetPointData().GetScalars().GetName()}' "
                "are drawn as missing data (like NaN); replace them first to draw them "
                "(e.g. numpy.nan_to_num)", InputWarning, stacklevel=2)
        array = numpy_to_vtk(np.ascontiguousarray(prepared.values).ravel(), deep=True)
        array.SetName(source.GetPointData().GetScalars().GetName() or "scalars")
        _copy_structure(target, source)
        target.GetPointData().SetScalars(array)
        return 1


def masked(image: vtkImageData, mask: vtkImageData) -> vtkImageData:
    """``image`` with the points where ``mask``'s scalars are 0 or less hidden (missing data), as VTK's binary
    masks leave out the samples where the mask is not above 0.

    A shallow copy (``image`` is not modified) with a ``vtkValidPointMask`` array
    (:func:`mipcast.core.prepare.hidden_points`), combined with one it has.

    Raises
    ------
    InputError
        If the mask has no point scalars, other dimensions than the image, or
        the image draws cell scalars.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> from mipcast.core.prepare import hidden_points
    >>> image = make_fixture("spheres", size=8)
    >>> mask = vtkImageData()
    >>> mask.SetDimensions(image.GetDimensions())
    >>> _ = mask.GetPointData().SetScalars(numpy_to_vtk((np.arange(512) % 2).astype(np.uint8), deep=True))
    >>> int(hidden_points(masked(image, mask)).sum()), hidden_points(image) is None
    (256, True)
    """
    scalars = mask.GetPointData().GetScalars()
    if scalars is None:
        raise InputError("the mask (SetMaskInput) has no point scalars: give it one array, above 0 where the "
                         "volume is drawn")
    if mask.GetDimensions() != image.GetDimensions():
        raise InputError(f"the mask (SetMaskInput) has dimensions {mask.GetDimensions()}, the volume "
                         f"{image.GetDimensions()}: a mask holds one value per point of the volume (resample it "
                         "onto the volume, e.g. vtkImageReslice with the volume as its information input)")
    if image.GetPointData().GetScalars() is None:
        raise InputError("a mask (SetMaskInput) hides points, and this volume draws cell scalars: convert them "
                         "to point scalars first (vtkCellDataToPointData)")
    values = vtk_to_numpy(scalars)
    inside = (values if values.ndim == 1 else values[:, 0]) > 0
    out = vtkImageData()
    out.ShallowCopy(image)
    valid = out.GetPointData().GetArray(VALID_POINT_MASK)
    if valid is not None and valid.GetNumberOfComponents() == 1:
        inside = inside & (vtk_to_numpy(valid) != 0)
    array = numpy_to_vtk(inside.astype(np.uint8), deep=True)
    array.SetName(VALID_POINT_MASK)
    out.GetPointData().AddArray(array)
    return out


def piece_range(preparer: InputPreparer) -> Optional[tuple]:
    """The finite (low, high) a piece of ``preparer``'s input fills its missing values against, or None.

    A brick of a volume beyond the 3D texture limit is drawn by its own
    mapper, whose preparer would fill its missing voxels relative to the
    brick's own finite range; given this (:meth:`InputPreparer.SetWholeRange`)
    it fills them, and sets its missing thresholds, as the whole volume does.
    None when the input holds no missing values (nothing to fill) or was
    refused; the whole range the input itself was given when it is a piece.

    Examples
    --------
    >>> import numpy as np
    >>> from vtkmodules.util.numpy_support import numpy_to_vtk
    >>> image = vtkImageData()
    >>> image.SetDimensions(2, 2, 2)
    >>> _ = image.GetPointData().SetScalars(numpy_to_vtk(np.array([0, 1, 2, 3, 4, 5, 6, np.nan]), deep=True))
    >>> preparer = InputPreparer()
    >>> preparer.SetInputDataObject(image)
    >>> piece_range(preparer)
    (0.0, 6.0)
    """
    preparer.Update()
    prepared = preparer.GetPrepared()
    if prepared is None or not prepared.missing:
        return None
    return preparer.GetWholeRange() or (prepared.low, prepared.high)


def fill_side(projection: str) -> str:
    """Where a projection's missing voxels are filled: ``"above"`` for ``"minip"``, else ``"below"``.

    Examples
    --------
    >>> fill_side("minip"), fill_side("average")
    ('above', 'below')
    """
    return "above" if projection == "minip" else "below"


def prepared_image(image: vtkImageData, component=None, missing_allowed: bool = True,
                   projection: str = "mip") -> vtkImageData:
    """A new image holding what the GPU draws from ``image`` (``image`` itself if nothing changes; cell
    scalars: the image of the cell centres, :func:`mipcast.core.prepare.cell_centres`).

    For VTK's own mappers (stock, CPU), which have no preparer inside.
    ``missing_allowed=False``: refuse missing values.  ``projection``
    (``"mip"``, ``"minip"``, ``"average"``): missing voxels are filled above
    the data for MinIP, below it otherwise (:func:`fill_side`); see
    :func:`missing_as_background` for the rest of what VTK's mappers need.

    Raises
    ------
    InputError
        As :func:`mipcast.core.prepare.prepare_scalars`, or missing values where they are not allowed.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("spheres", size=8)
    >>> prepared_image(image) is image
    True
    """
    prepared = prepare_scalars(image, component, fill_side(projection))
    warn_if_far_from_origin(image)
    if prepared.missing and not missing_allowed:
        raise InputError(f"{prepared.missing} NaN/Inf voxels: missing data cannot be drawn here; "
                         "replace them first (e.g. numpy.nan_to_num)")
    image = scalar_image(image)  # cell scalars: the image of the cell centres
    if projection == "average" and not prepared.missing and not prepared.high > prepared.low:
        _warn_constant_average(image)
    return _with_values(image, prepared.values) if prepared.changed else image


def window_image(image: vtkImageData, component=None, whole_range=None) -> vtkImageData:
    """The image a default window is chosen from: the values the GPU draws (:func:`prepared_image`), with
    missing voxels left NaN.

    Whatever a projection fills missing voxels with (below the data for MIP and average, above for MinIP),
    they are no data: a window chosen with the fill in the histogram would put MinIP's window below every
    finite value, or, where most voxels are missing, a MIP's there too (:mod:`mipcast.core.windowing`
    leaves non-finite values out).  ``whole_range``: as :func:`mipcast.core.validation.check_image`'s.

    Examples
    --------
    >>> import numpy as np
    >>> from mipcast.core.windowing import resolve_window
    >>> from mipcast.data_fixtures.synthetic import image_from_array
    >>> values = np.linspace(0.0, 1.0, 64).reshape(4, 4, 4); values[0] = np.nan
    >>> resolve_window(window_image(image_from_array(values)), "full")
    (0.25396825396825395, 1.0)
    """
    prepared = prepare_scalars(image, component, whole_range=whole_range)
    source = scalar_image(image)  # cell scalars: the image of the cell centres
    if not prepared.changed:
        return source
    return _with_values(source, prepared.seen(np.asarray(prepared.values, np.float64)) if prepared.missing
                        else prepared.values)


def _copy_structure(target: vtkImageData, source: vtkImageData) -> None:
    """``source``'s structure on ``target``, without its ghost array: the hidden points are missing data in
    the prepared values (:func:`mipcast.core.prepare.hidden_points`); VTK's ray caster would hide them its way."""
    target.CopyStructure(source)
    target.GetPointData().RemoveArray(vtkDataSetAttributes.GhostArrayName())


def _with_values(image: vtkImageData, values: np.ndarray) -> vtkImageData:
    """A new image of ``image``'s structure whose point scalars are ``values`` (named as ``image``'s scalars),
    with its field data (a DICOM volume's ``"units"``: the default window's CT rule reads it)."""
    out = vtkImageData()
    _copy_structure(out, image)
    out.GetFieldData().ShallowCopy(image.GetFieldData())
    array = numpy_to_vtk(np.ascontiguousarray(values).ravel(), deep=True)
    array.SetName(image.GetPointData().GetScalars().GetName() or "scalars")
    out.GetPointData().SetScalars(array)
    return out


def warn_if_far_from_origin(image: vtkImageData) -> None:
    """Once per origin: a :class:`mipcast.InputWarning` where ``image`` lies too far from the origin for the GPU's
    float32 rays (:func:`mipcast.core.validation.far_from_origin`); not again for the coarser copies a method
    draws of the same volume (foveation's pyramid), which share its origin."""
    stamp = (tuple(image.GetOrigin()), "far from the origin")
    if stamp in _WARNED:
        return
    reason = far_from_origin(image)
    if reason is not None:
        _WARNED.add(stamp)
        warnings.warn(reason[0].upper() + reason[1:], InputWarning, stacklevel=3)


def _warn_constant_average(image: vtkImageData) -> None:
    """Once per volume: VTK's own average draws this constant volume black, and why."""
    scalars = image.GetPointData().GetScalars()
    stamp = (scalars.GetAddressAsString("vtkObjectBase"), scalars.GetMTime(), "constant average")
    if stamp in _WARNED:
        return
    _WARNED.add(stamp)
    warnings.warn(
        f"'{scalars.GetName()}' is constant: VTK's own AVERAGE_INTENSITY blend (stock_average) averages the "
        "samples normalised over the data range, which is empty here, so it draws the volume black; use "
        "mipcast's 'average' or 'analytic_average', which draw the mean in data units", InputWarning,
        stacklevel=3)


#: Where :func:`missing_as_background`'s opacity ramp starts and ends, in data ranges beyond the finite extreme.
RAMP = (1.0 / 512.0, 1.0 / 128.0)
#: The average's weights drop to 0 this fraction of (low - fill) below the finite minimum.
MISSING_RAMP_BELOW = 1.0 / 256.0


def missing_as_background(mapper, volume_property, image: vtkImageData, component=None,
                          projection: str = "mip"):
    r"""What a VTK mapper (stock, CPU) needs to draw a ray that saw only missing data as background.

    VTK's own mappers have no per-ray missing test: they draw the prepared
    copy (:func:`prepared_image`) and a ray that crossed only missing voxels
    takes the fill's colour.  For input with missing values this returns a
    copy of ``volume_property`` whose scalar opacity is 0 on the fill's side
    of the data, from :data:`RAMP`\ [1] of the data range beyond the finite
    extreme to the fill, ramping to the original opacity at :data:`RAMP`\ [0]
    (VTK samples the transfer functions into tables and interpolates between
    entries: every finite value keeps its opacity; a ray whose extreme lies
    within the ramp, pulled there by missing neighbours, is partly
    transparent), and for the average sets the mapper's
    ``AverageIPScalarRange`` to start at the finite floor (samples pulled
    below it do not count; a ray with none draws nothing, as stock does).
    Without missing values it returns ``volume_property`` itself and resets
    the average's range to VTK's default.  ``volume_property`` is not modified.

    Examples
    --------
    >>> import numpy as np
    >>> from vtkmodules.util.numpy_support import numpy_to_vtk
    >>> from vtkmodules.vtkRenderingCore import vtkVolumeProperty
    >>> from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper
    >>> image = vtkImageData()
    >>> image.SetDimensions(2, 2, 2)
    >>> _ = image.GetPointData().SetScalars(numpy_to_vtk(np.array([0, 1, 2, 3, 4, 5, 6, np.nan]), deep=True))
    >>> prop = vtkVolumeProperty()
    >>> prop.GetScalarOpacity().AddPoint(0.0, 1.0)
    0
    >>> drawn = missing_as_background(vtkOpenGLGPUVolumeRayCastMapper(), prop, image)
    >>> drawn is prop, drawn.GetScalarOpacity().GetValue(-6.0), drawn.GetScalarOpacity().GetValue(0.0)
    (False, 0.0, 1.0)
    """
    from vtkmodules.vtkRenderingCore import vtkVolumeProperty

    prepared = prepare_scalars(image, component, fill_side(projection))
    average = projection == "average" and hasattr(mapper, "SetAverageIPScalarRange")
    if not prepared.missing:
        if average:
            mapper.SetAverageIPScalarRange(-3.4028234663852886e38, 3.4028234663852886e38)  # VTK's default
        return volume_property
    span = prepared.high - prepared.low if prepared.high > prepared.low else max(abs(prepared.low), 1.0)
    drawn = vtkVolumeProperty()
    drawn.DeepCopy(volume_property)
    opacity = drawn.GetScalarOpacity()
    if average:  # the mean over the finite samples, its grey over the finite range (as mipcast's average)
        mapper.SetAverageIPScalarRange(prepared.missing_below, 3.4028234663852886e38)
        _average_grey_over_finite_range(opacity, prepared, drawn.GetRGBTransferFunction(0).GetRange())
        return drawn
    above = fill_side(projection) == "above"
    edge = prepared.high if above else prepared.low
    kept = opacity.GetValue(edge)
    nodes = [[0.0] * 4 for _ in range(opacity.GetSize())]
    for index, node in enumerate(nodes):
        opacity.GetNodeValue(index, node)
    for x, *_ in nodes:  # no finite value lies beyond the extreme: only fill and values it pulled
        if (x > edge) if above else (x < edge):
            opacity.RemovePoint(x)
    direction = 1.0 if above else -1.0
    opacity.AddPoint(edge, kept)
    opacity.AddPoint(edge + direction * span * RAMP[0], kept)  # VTK's tables interpolate between entries
    opacity.AddPoint(edge + direction * span * RAMP[1], 0.0)
    opacity.AddPoint(prepared.fill, 0.0)
    return drawn


def _average_grey_over_finite_range(opacity, prepared, window=None) -> None:
    """Make VTK's average grey the normalisation over the finite range, through its opacity weights.

    VTK's AVERAGE_INTENSITY blend draws the mean of ``opacity(s) * s``, ``s``
    normalised over the texture's range, which the fill widens to
    ``[fill, high]``; weighting each sample by ``t(v) / s(v)`` (``t`` the
    normalisation over :func:`~mipcast.core.prepare.shade_range`, in [0, 1])
    turns it into the mean of ``opacity(v) t(v)``, as mipcast's average draws.
    ``t / s`` is smooth: 64 linear pieces over the finite range (within
    1e-4 of it), 0 below.
    """
    low, high = prepared.low, prepared.high
    glow, ghigh = shade_range(prepared, window)
    fill = prepared.fill
    values = np.linspace(low, high, 65) if high > low else np.array([low])
    kept = [opacity.GetValue(float(v)) for v in values]
    opacity.RemoveAllPoints()
    for v, weight in zip(values, kept):
        s = (v - fill) / (high - fill)
        t = min(max((v - glow) / (ghigh - glow), 0.0), 1.0)
        opacity.AddPoint(float(v), float(min(1.0, weight * t / s)))
    opacity.AddPoint(float(low - MISSING_RAMP_BELOW * (low - fill)), 0.0)
    opacity.AddPoint(float(fill), 0.0)

"""Read a volume file into a ``vtkImageData`` that the renderers accept.

Every reader's output is copied into a fresh ``vtkImageData`` (shallow: the
voxels are shared, the reader is not kept), given its patient-space geometry
(origin, spacing, direction matrix) and validated with
:func:`mipcast.core.validation.check_image`.

World coordinates are DICOM's LPS (+x patient left, +y posterior, +z
superior) for every format that records a patient frame, so the same scan
read from DICOM, NIfTI, NRRD or MetaImage lands at the same place:

- DICOM: LPS by definition (see :mod:`mipcast.io.dicom`).
- NIfTI: the header maps voxels to RAS; the chosen qform/sform is turned
  into origin + spacing + direction and then converted to LPS (x and y
  negated), as ITK and SimpleITK do.
- NRRD (pynrrd): ``space directions``/``space origin`` are applied,
  converted to LPS from the ``space`` named in the header (RAS, LAS or LPS;
  ``scanner-xyz`` and ``3D-*`` spaces are kept).
- MetaImage: ``Offset``/``TransformMatrix`` as read by VTK (ITK writes LPS).
- VTK XML (.vti): origin, spacing and direction as stored.

A left-handed direction matrix (determinant -1, e.g. a NIfTI sform with a
flip) is made right-handed by reversing the slice order and flipping the
third direction column: every voxel keeps its value and its position.
"""
from __future__ import annotations

import contextlib
import os
import re
import warnings
import zlib
from pathlib import Path
from typing import Optional, Tuple, Union

import numpy as np
from vtkmodules.util.numpy_support import get_vtk_array_type, numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDataArray, vtkLogger, vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkImageData, vtkRectilinearGrid
from vtkmodules.vtkIOImage import vtkMetaImageReader, vtkNIFTIImageReader
from vtkmodules.vtkIOLegacy import vtkDataSetReader
from vtkmodules.vtkIOXML import (vtkXMLImageDataReader, vtkXMLMultiBlockDataReader,
                                 vtkXMLPartitionedDataSetCollectionReader, vtkXMLPartitionedDataSetReader,
                                 vtkXMLPImageDataReader, vtkXMLRectilinearGridReader)

from mipcast.core.camera_rays import matrix_array
from mipcast.core.prepare import cell_centres
from mipcast.io.composite import one_image
from mipcast.io.dicom import caller_level, integer_dtype
from mipcast.core.validation import check_image

PathLike = Union[str, "os.PathLike[str]"]

#: Extensions read by :func:`read_volume` (a folder is read as a DICOM series).
SUPPORTED_EXTENSIONS = (".vti", ".pvti", ".vtr", ".vtk", ".vtm", ".vtpd", ".vtpc", ".nrrd", ".nhdr", ".nii",
                        ".nii.gz", ".mha", ".mhd", ".tif", ".tiff", ".dcm", ".dicom")

_RAS_TO_LPS = np.diag([-1.0, -1.0, 1.0])
_NRRD_SPACES = {  # NRRD 'space' -> matrix taking its coordinates to LPS
    "left-posterior-superior": np.eye(3), "lps": np.eye(3),
    "right-anterior-superior": _RAS_TO_LPS, "ras": _RAS_TO_LPS,
    "left-anterior-superior": np.diag([1.0, -1.0, 1.0]), "las": np.diag([1.0, -1.0, 1.0]),
}


def read_volume(path: PathLike, *, series_uid: Optional[str] = None, volume: Optional[int] = None,
                padding: str = "missing") -> vtkImageData:
    """Read a volume file or a DICOM folder as a validated ``vtkImageData``.

    Parameters
    ----------
    path : str or os.PathLike
        ``.vti`` (VTK XML image data), ``.pvti`` (its parallel pieces),
        ``.vtr`` (an evenly spaced XML rectilinear grid), ``.vtk`` (legacy
        structured points or an evenly spaced rectilinear grid), ``.vtm`` /
        ``.vtpd`` / ``.vtpc`` (XML multiblock / partitioned data (collection)
        holding one volume or image pieces of one grid: :func:`mipcast.io.composite.one_image`),
        ``.nrrd``/``.nhdr``, ``.nii``/``.nii.gz`` (NIfTI-1/2), ``.mha``/``.mhd``
        (MetaImage), ``.tif``/``.tiff`` (a microscope's stack: ImageJ
        hyperstacks, OME-TIFF, plain pages; :mod:`mipcast.io.tiff`), a
        ``.dcm`` file or a folder of DICOM files.  A file with
        another extension is read as DICOM if it carries the DICOM marker
        ('DICM' at byte 128).  A VTK file that names no active scalars
        (pyvista's ``save``, ParaView's writers) has its first numeric point
        array (else cell array) active.
    series_uid : str, optional
        For a DICOM folder holding several series: which one to read (see
        :func:`mipcast.io.dicom.list_series`).
    volume : int, optional
        For a 4D NIfTI or NRRD file (a time series: fMRI, perfusion, DCE, 4D
        CT; a DWI's gradients): which volume to read, from 0; default the
        first, with a warning that names how many there are; for a TIFF
        stack, which time point (``T``).  For a
        ``.vtm`` / ``.vtpd`` / ``.vtpc`` file: which of its non-empty data
        sets, from 0 (default: its one volume).
    padding : {"missing", "keep"}
        For DICOM: the pixels holding the series' PixelPaddingValue (outside
        a CT's field of view) are read as missing data (NaN), or kept as
        values (see :func:`mipcast.io.dicom.read_dicom`).

    Returns
    -------
    vtkImageData
        A new image (not tied to any reader) with one-component point
        scalars, at least 2 points along every axis.

        - NIfTI: the sform is used if its code is > 0 and it is a rotation
          times a scale, else the qform if its code is > 0 (VTK's reader
          has already reordered the slices when qfac = -1), else no
          orientation (origin 0, identity directions) -- "method 1" of the
          NIfTI standard; a sheared sform without a qform falls back to that
          with a warning.  The result is converted from RAS to LPS.
          ``scl_slope``/``scl_inter`` are applied when set (slope not 0 and
          not 1 or intercept not 0): float32, or int16/int32 for integer
          factors.  Of a 4D file one volume is read: ``volume`` (a warning
          says how many there are when it is not given).
        - NRRD (read by pynrrd, scalars ``"values"``): three spatial axes
          plus at most one more, whose samples are components (a vector,
          colour or tensor kind, or no kind on the first axis) or volumes
          (``list``, ``time``: a time series, a DWI's gradients), of which
          ``volume`` is read (a warning says how many there are when it is
          not given).  A MetaImage of more than 3 dimensions is refused
          from its header (VTK's reader corrupts memory on it).
        - DICOM: see :func:`mipcast.io.dicom.read_dicom` (scalars ``"values"``
          in the modality's units, e.g. HU for CT, a ``"units"`` field array).

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist (the message names it).
    ValueError
        For an unsupported extension (the message lists the supported ones),
        a file the reader cannot parse (the reader's own messages are
        included), a VTK file holding no image data (a mesh: resample it),
        or a volume :func:`mipcast.core.validation.check_image` refuses (its
        message is kept, e.g. "at least 2 points are needed along every
        axis" for a single DICOM slice).
    TypeError
        From :func:`mipcast.core.validation.check_image` (unsupported scalar
        type); for a rectilinear grid whose steps are uneven (resample it).

    Examples
    --------
    >>> import os, tempfile
    >>> from vtkmodules.vtkIOXML import vtkXMLImageDataWriter
    >>> from mipcast.data_fixtures import make_fixture
    >>> path = os.path.join(tempfile.mkdtemp(), "spheres.vti")
    >>> writer = vtkXMLImageDataWriter()
    >>> writer.SetFileName(path)
    >>> writer.SetInputData(make_fixture("spheres", size=16))
    >>> writer.Write()
    1
    >>> read_volume(path).GetDimensions()
    (16, 16, 16)

    A DICOM folder (pydicom's 5-slice CT test series):

    >>> from pydicom.data import get_testdata_file
    >>> folder = os.path.dirname(get_testdata_file("dicomdirtests/98892001/CT5N/2062"))
    >>> image = read_volume(folder)
    >>> image.GetDimensions(), image.GetPointData().GetScalars().GetName()
    ((16, 16, 5), 'values')
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no such file or folder: '{path}'")
    kind = _kind(path)
    if kind == "dicom":
        from mipcast.io.dicom import read_dicom

        image = _fresh(read_dicom(path, series_uid=series_uid, padding=padding))
        try:
            check_image(image)
        except ValueError as error:
            if path.is_file() and image.GetDimensions()[2] == 1:
                raise ValueError(
                    f"{error} ('{path}' is a single DICOM slice: pass the folder that holds "
                    "the whole series)") from None
            raise
        return image
    if series_uid is not None:
        raise ValueError(f"series_uid applies to DICOM input only, not to '{path}'")
    if kind == "nifti":
        image = _read_nifti(path, volume)
    elif kind == "nrrd":
        image = _read_nrrd(path, volume)
    elif kind == "tiff":
        from mipcast.io.tiff import read_tiff

        image = read_tiff(path, volume)
    elif volume is not None and kind not in _COMPOSITE_KINDS:
        raise ValueError(f"volume picks a volume of a 4D NIfTI or NRRD file, a time point of a TIFF stack or a "
                         f"data set of a .vtm, .vtpd or "
                         f".vtpc file, not of '{path}' (a DICOM folder's volumes are picked with series_uid, see "
                         "mipcast.io.dicom.list_series)")
    else:
        image = _read_meta(path) if kind == "meta" else _read_vtk_file(path, kind, volume)
    image = right_handed(image)
    check_image(image)
    return image


# ---------------------------------------------------------------------------
# dispatch
# ---------------------------------------------------------------------------

def _kind(path: Path) -> str:
    if path.is_dir():
        return "dicom"
    name = path.name.lower()
    for suffix, kind in ((".vti", "vti"), (".pvti", "pvti"), (".vtr", "vtr"), (".vtk", "legacy"),
                         (".vtm", "vtm"), (".vtpd", "vtpd"), (".vtpc", "vtpc"),
                         (".nrrd", "nrrd"), (".nhdr", "nrrd"),
                         (".nii", "nifti"), (".nii.gz", "nifti"), (".mha", "meta"),
                         (".mhd", "meta"), (".tif", "tiff"), (".tiff", "tiff"), (".dcm", "dicom"),
                         (".dicom", "dicom")):
        if name.endswith(suffix):
            return kind
    if _has_dicom_marker(path):
        return "dicom"
    raise ValueError(
        f"cannot read '{path}': unknown file type '{''.join(path.suffixes) or '(no extension)'}'; "
        f"supported: {', '.join(SUPPORTED_EXTENSIONS)}, a DICOM file with the 'DICM' marker, "
        "or a folder of DICOM files")


def _has_dicom_marker(path: Path) -> bool:
    try:
        with open(path, "rb") as handle:
            handle.seek(128)
            return handle.read(4) == b"DICM"
    except OSError:
        return False


# ---------------------------------------------------------------------------
# running a VTK reader with its messages captured
# ---------------------------------------------------------------------------

@contextlib.contextmanager
def _captured_vtk_messages():
    """Collect VTK's error/warning text (and keep it off stderr) while reading."""
    previous = vtkOutputWindow.GetInstance()
    window = vtkStringOutputWindow()
    verbosity = vtkLogger.GetCurrentVerbosityCutoff()
    vtkOutputWindow.SetInstance(window)
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    try:
        yield window
    finally:
        vtkOutputWindow.SetInstance(previous)
        vtkLogger.SetStderrVerbosity(vtkLogger.ConvertToVerbosity(verbosity))


def _run(reader, path: Path, what: str) -> vtkImageData:
    """Update ``reader`` on ``path``; return a fresh copy of its output or raise."""
    if not reader.CanReadFile(str(path)):
        raise ValueError(f"cannot read '{path}': it is not a valid {what} file "
                         "(the reader does not recognise its header)")
    reader.SetFileName(str(path))
    with _captured_vtk_messages() as window:
        reader.Update()
    messages = window.GetOutput()
    output = reader.GetOutput()
    failed = ("ERROR" in messages or "File operation failed" in messages
              or reader.GetErrorCode() != 0 or output is None
              or (not isinstance(output, vtkCompositeDataSet)  # (its data sets are checked as the one drawn)
                  and (output.GetNumberOfPoints() == 0
                       or not (_numeric_names(output.GetPointData()) or _numeric_names(output.GetCellData())))))
    if failed:
        detail = " ".join(line.strip() for line in messages.splitlines()
                          if line.strip() and not line.startswith(("ERROR: In", "Warning: In",
                                                                   "Generic Warning: In")))
        detail = re.sub(r"\s*\(0x[0-9a-f]+\)", "", detail)[:500]
        raise ValueError(f"cannot read '{path}' as {what}: the file is damaged or incomplete"
                         + (f" (VTK: {detail})" if detail else ""))
    copy = output.NewInstance()
    copy.ShallowCopy(output)
    return copy


def _fresh(source: vtkImageData) -> vtkImageData:
    image = vtkImageData()
    image.ShallowCopy(source)
    return image


def _set_geometry(image: vtkImageData, origin, spacing, direction) -> None:
    image.SetOrigin(*(float(v) for v in origin))
    image.SetSpacing(*(float(v) for v in spacing))
    image.SetDirectionMatrix(*np.asarray(direction, dtype=float).ravel())


def _split(columns: np.ndarray) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """(unit directions, lengths) of the columns of a 3x3 matrix, or None if sheared."""
    lengths = np.linalg.norm(columns, axis=0)
    if not (lengths > 0).all():
        return None
    unit = columns / lengths
    if np.abs(unit.T @ unit - np.eye(3)).max() > 1e-4:
        return None
    return unit, lengths


def right_handed(image: vtkImageData) -> vtkImageData:
    """``image`` itself, or, if its direction matrix is left-handed (a reflection), the same volume right-handed.

    VTK's GPU ray caster (stock and mipcast's) draws a volume whose direction
    matrix has determinant -1 wrong: its rays enter through the far faces, a
    nearly blank picture (mipcast's mappers refuse it). The copy reverses the
    slice order of every point and cell array and negates the third direction
    column, moving the origin to the last slice: every voxel keeps its value
    and its position (arrays that are not numeric are left out). ``image`` is
    not modified.

    Examples
    --------
    >>> import numpy as np
    >>> from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    >>> image = vtkImageData()
    >>> image.SetDimensions(2, 2, 3)
    >>> image.SetDirectionMatrix(1, 0, 0, 0, 1, 0, 0, 0, -1)
    >>> _ = image.GetPointData().SetScalars(numpy_to_vtk(np.arange(12.0), deep=True))
    >>> fixed = right_handed(image)
    >>> fixed.GetOrigin(), fixed.GetDirectionMatrix().GetElement(2, 2), vtk_to_numpy(fixed.GetPointData().GetScalars())[:4].tolist()
    ((0.0, 0.0, -2.0), 1.0, [8.0, 9.0, 10.0, 11.0])
    """
    direction = matrix_array(image.GetDirectionMatrix())
    if np.linalg.det(direction) > 0:
        return image
    nx, ny, nz = image.GetDimensions()
    spacing = np.array(image.GetSpacing())
    origin = np.array(image.GetOrigin()) + direction[:, 2] * spacing[2] * (nz - 1)
    direction[:, 2] *= -1
    flipped = _fresh(image)
    for data, target, slices in ((image.GetPointData(), flipped.GetPointData(), nz),
                                 (image.GetCellData(), flipped.GetCellData(), max(nz - 1, 1))):
        target.Initialize()  # numeric arrays only, reversed (a string array per point is not drawn)
        for index in range(data.GetNumberOfArrays()):
            array = data.GetArray(index)
            if array is None:
                continue
            values = vtk_to_numpy(array).reshape(slices, -1, array.GetNumberOfComponents())[::-1]
            copy = vtkDataArray.CreateDataArray(array.GetDataType())
            copy.SetName(array.GetName())
            copy.SetNumberOfComponents(array.GetNumberOfComponents())
            copy.SetNumberOfTuples(array.GetNumberOfTuples())
            vtk_to_numpy(copy).reshape(values.shape)[...] = values
            if data.GetScalars() is array:
                target.SetScalars(copy)
            else:
                target.AddArray(copy)
    _set_geometry(flipped, origin, spacing, direction)
    return flipped


# ---------------------------------------------------------------------------
# formats
# ---------------------------------------------------------------------------

#: The composite formats (:func:`mipcast.io.composite.one_image`), whose data set ``volume`` picks.
_COMPOSITE_KINDS = ("vtm", "vtpd", "vtpc")

_VTK_FORMATS = {"vti": (vtkXMLImageDataReader, "VTK XML image data (.vti)"),
                "pvti": (vtkXMLPImageDataReader, "VTK XML parallel image data (.pvti)"),
                "vtr": (vtkXMLRectilinearGridReader, "VTK XML rectilinear grid (.vtr)"),
                "legacy": (vtkDataSetReader, "legacy VTK (.vtk)"),
                "vtm": (vtkXMLMultiBlockDataReader, "VTK XML multiblock data (.vtm)"),
                "vtpd": (vtkXMLPartitionedDataSetReader, "VTK XML partitioned data set (.vtpd)"),
                "vtpc": (vtkXMLPartitionedDataSetCollectionReader, "VTK XML partitioned data set collection (.vtpc)")}


def _read_vtk_file(path: Path, kind: str, index: Optional[int] = None) -> vtkImageData:
    """A VTK file of image data or an evenly spaced rectilinear grid, with active scalars (the first numeric
    point array, else cell array, where the file names none: pyvista and ParaView write such files); of a
    composite file its one volume, or its data set ``index``."""
    reader_type, what = _VTK_FORMATS[kind]
    reader = reader_type()
    if kind == "legacy":
        reader.ReadAllScalarsOn()
        reader.ReadAllVectorsOn()
    data = _run(reader, path, what)
    if isinstance(data, vtkCompositeDataSet):
        data = one_image(data, index)
    if isinstance(data, vtkRectilinearGrid):
        data = as_image_data(data)
    if not isinstance(data, vtkImageData):
        raise ValueError(
            f"cannot draw '{path}': it holds a {data.GetClassName()[3:]}, not image data; resample it onto "
            "image data first (ParaView: Resample To Image; pyvista: grid.sample(pyvista.ImageData(...)); VTK: "
            "vtkResampleToImage) and save that (.vti)")
    if data.GetPointData().GetScalars() is None and data.GetCellData().GetScalars() is None:
        for attributes in (data.GetPointData(), data.GetCellData()):
            names = _numeric_names(attributes)
            if names:
                attributes.SetActiveScalars(names[0])
                break
    return data


def _numeric_names(attributes) -> list:
    """Names of the numeric arrays of point or cell data, in order."""
    return [attributes.GetArrayName(i) for i in range(attributes.GetNumberOfArrays())
            if attributes.GetArray(i) is not None]


def _read_meta(path: Path) -> vtkImageData:
    dimensions = _meta_header(path).get("ndims", "3")
    if dimensions.strip() not in ("2", "3"):  # VTK's reader logs an error and corrupts the heap (a crash later)
        raise ValueError(
            f"cannot read '{path}': it is a {dimensions}-dimensional MetaImage (NDims = {dimensions}) and VTK's "
            "MetaImage reader reads 2D and 3D images only; save each volume as its own file (SimpleITK: "
            "sitk.WriteImage(image[:, :, :, k], 'volume_k.mha')) or the series as .nii.gz and pass volume=K")
    return _run(vtkMetaImageReader(), path, "MetaImage (.mha/.mhd)")


def _meta_header(path: Path) -> dict:
    """The ``Key = Value`` lines of a MetaImage header up to ``ElementDataFile``, keys lower-cased."""
    with open(path, "rb") as handle:
        text = handle.read(1 << 16).decode("latin-1")
    fields = {}
    for line in text.splitlines():
        key, equals, value = line.partition("=")
        if not equals:
            break
        fields[key.strip().lower()] = value.strip()
        if key.strip().lower() == "elementdatafile":
            break
    return fields


def _read_nifti(path: Path, volume: Optional[int] = None) -> vtkImageData:
    reader = vtkNIFTIImageReader()
    if volume is not None:
        if isinstance(volume, bool) or not isinstance(volume, (int, np.integer)) or volume < 0:
            raise ValueError(f"volume must be an integer >= 0 (the first volume is 0), got {volume!r}")
        reader.TimeAsVectorOn()  # every volume, as blocks of components: volume k's are k*C .. k*C + C - 1
    image = _run(reader, path, "NIfTI (.nii/.nii.gz)")
    header = reader.GetNIFTIHeader()
    count = reader.GetTimeDimension()
    number = volume_number(path, count, volume, kind="4D NIfTI")
    if volume is not None:
        _keep_volume(image, number, count)
    spacing = np.array(image.GetSpacing())
    geometry = None
    sform, qform = reader.GetSFormMatrix(), reader.GetQFormMatrix()
    if header.GetSFormCode() > 0 and sform is not None:
        matrix = matrix_array(sform)
        split = _split(matrix[:3, :3])
        if split is not None:
            geometry = (matrix[:3, 3], spacing * split[1], split[0])
    if geometry is None and header.GetQFormCode() > 0 and qform is not None:
        matrix = matrix_array(qform)
        split = _split(matrix[:3, :3])
        if split is not None:
            geometry = (matrix[:3, 3], spacing * split[1], split[0])
    if geometry is None and header.GetSFormCode() > 0:
        warnings.warn(f"'{path}': the sform is sheared (not a rotation and scale) and there is "
                      "no qform; the orientation is ignored (origin 0, axes along x, y, z)",
                      stacklevel=caller_level())
    if geometry is not None:
        origin, spacing, direction = geometry
        _set_geometry(image, _RAS_TO_LPS @ origin, spacing, _RAS_TO_LPS @ direction)
    slope, intercept = reader.GetRescaleSlope(), reader.GetRescaleIntercept()
    if np.isfinite(slope) and slope != 0 and (slope != 1 or intercept != 0):
        _rescale(image, slope, intercept)
    return image


def _keep_volume(image: vtkImageData, volume: int, count: int) -> None:
    """Replace the scalars that hold ``count`` volumes as blocks of components by volume ``volume``'s (a new array)."""
    scalars = image.GetPointData().GetScalars()
    components = scalars.GetNumberOfComponents() // count
    values = vtk_to_numpy(scalars).reshape(scalars.GetNumberOfTuples(), count * components)
    array = vtkDataArray.CreateDataArray(scalars.GetDataType())
    array.SetName(scalars.GetName() or "scalars")
    array.SetNumberOfComponents(components)
    array.SetNumberOfTuples(scalars.GetNumberOfTuples())
    vtk_to_numpy(array).reshape(-1, components)[...] = values[:, volume * components:(volume + 1) * components]
    image.GetPointData().SetScalars(array)


def _rescale(image: vtkImageData, slope: float, intercept: float) -> None:
    """Replace the scalars by ``value * slope + intercept`` (a new array)."""
    scalars = image.GetPointData().GetScalars()
    values = vtk_to_numpy(scalars)
    if values.dtype.kind in "iub" and float(slope).is_integer() and float(intercept).is_integer():
        ends = np.array([values.min(), values.max()], dtype=float) * slope + intercept
        dtype = integer_dtype(ends.min(), ends.max())
    else:
        dtype = np.dtype(np.float32)
    array = vtkDataArray.CreateDataArray(get_vtk_array_type(dtype))
    array.SetName(scalars.GetName() or "scalars")
    array.SetNumberOfComponents(scalars.GetNumberOfComponents())
    array.SetNumberOfTuples(scalars.GetNumberOfTuples())
    out = vtk_to_numpy(array)
    work = np.int64 if dtype.kind in "iu" else np.float64
    out[...] = values.astype(work) * work(slope) + work(intercept)
    image.GetPointData().SetScalars(array)


#: NRRD axis kinds whose samples are a voxel's components (drawn as their magnitude, or one with component=K).
NRRD_COMPONENT_KINDS = frozenset(
    "vector covariant-vector normal 2-vector 3-vector 4-vector 3-gradient 3-normal complex quaternion "
    "rgb-color hsv-color xyz-color rgba-color 3-color 4-color 2d-symmetric-matrix 2d-masked-symmetric-matrix "
    "2d-matrix 2d-masked-matrix 3d-symmetric-matrix 3d-masked-symmetric-matrix 3d-matrix 3d-masked-matrix "
    "point".split())


def _read_nrrd(path: Path, volume: Optional[int] = None) -> vtkImageData:
    """A NRRD file (any encoding, attached or detached data) read by pynrrd, the reference reader.

    Three spatial axes (those with ``space directions``, else of kind
    ``domain``/``space``, else the first three) plus at most one more: its
    samples are components when its kind is a vector, colour, tensor ...
    kind (:data:`NRRD_COMPONENT_KINDS`, or no kind on the first axis), else
    volumes (``list``, ``time``, a DWI's gradients), of which ``volume``
    is read (default the first, with a warning naming how many).
    """
    import nrrd

    try:
        data, header = nrrd.read(str(path))
    except (nrrd.NRRDError, ValueError, EOFError, OSError, zlib.error) as error:
        raise ValueError(f"cannot read '{path}' as NRRD (.nrrd/.nhdr): the file is damaged or incomplete "
                         f"({error})") from error
    sizes = list(data.shape)
    kinds = [str(k).lower() for k in header.get("kinds", [])]
    spatial = _nrrd_spatial_axes(header, kinds, len(sizes))
    others = [axis for axis in range(len(sizes)) if axis not in spatial]
    described = "sizes " + " ".join(map(str, sizes)) + (", kinds " + " ".join(kinds) if kinds else "")
    if len(spatial) != 3 or len(others) > 1:
        raise ValueError(
            f"cannot read '{path}': {len(sizes)} axes ({described}), {len(spatial)} of them spatial; mipcast "
            "reads three spatial axes plus at most one of components or volumes: slice it (`unu slice`) first")
    values = np.moveaxis(data, spatial, [0, 1, 2])  # (x, y, z[, other])
    if others:
        kind = kinds[others[0]] if kinds else ("vector" if others[0] == 0 else "list")
        if kind in NRRD_COMPONENT_KINDS:
            if volume is not None and volume != 0:
                raise ValueError(f"'{path}' holds one volume of {sizes[others[0]]} components ({kind}); there is no "
                                 f"volume {volume} (pass component=K to draw one component)")
        else:
            along = f"along its axis {others[0]}"
            values = values[..., volume_number(path, sizes[others[0]], volume, (f"volume {along}", f"volumes {along}"),
                                               kind)]
    elif volume is not None and volume != 0:
        raise ValueError(f"'{path}' holds 1 volume (volume 0); there is no volume {volume}")
    image = vtkImageData()
    image.SetDimensions(*values.shape[:3])
    native = values.dtype.newbyteorder("=")
    points = np.ascontiguousarray(values.transpose((2, 1, 0) + tuple(range(3, values.ndim))), dtype=native)
    # (``points`` is ours, pynrrd's buffer or its contiguous copy: VTK keeps it alive, no second copy)
    array = numpy_to_vtk(points.reshape(-1, *values.shape[3:]) if values.ndim > 3 else points.ravel(), deep=False)
    array.SetName("values")
    image.GetPointData().SetScalars(array)
    _nrrd_geometry(path, image, header, spatial)
    return image


def _nrrd_spatial_axes(header: dict, kinds: list, ndim: int) -> list:
    directions = header.get("space directions")
    if directions is not None:
        rows = [np.asarray(d, dtype=float) if d is not None else None for d in directions]
        return [axis for axis, d in enumerate(rows) if d is not None and np.all(np.isfinite(d))]
    if kinds:
        return [axis for axis, kind in enumerate(kinds) if kind in ("domain", "space")]
    return list(range(min(ndim, 3)))


def volume_number(path: Path, count: int, volume: Optional[int], noun: tuple = ("volume", "volumes"),
                  kind: str = "") -> int:
    """Which of a file's ``count`` volumes to read: ``volume``, checked, or 0 (a warning says how many when
    there are several).  ``noun``: one volume of the file and several (``("time point", "time points")``),
    ``kind`` what they are (``4D NIfTI``, a NRRD axis's kind, ``T`` of a TIFF stack)."""
    one, many = noun
    if volume is None:
        if count > 1:
            warnings.warn(f"'{path}' holds {count} {many}{f' ({kind})' if kind else ''}; the first is read: pass "
                          f"volume=K (mipcast render/view --volume K), K from 0 to {count - 1}, for another",
                          stacklevel=caller_level())
        return 0
    if isinstance(volume, bool) or not isinstance(volume, (int, np.integer)) or volume < 0:
        raise ValueError(f"volume must be an integer >= 0 (the first volume is 0), got {volume!r}")
    if volume >= count:
        raise ValueError(f"'{path}' holds {count} {many if count > 1 else one} ({f'{kind}; ' if kind else ''}volume 0"
                         f"{f' to {count - 1}' if count > 1 else ''}); there is no volume {volume}")
    return int(volume)


def _nrrd_geometry(path: Path, image: vtkImageData, header: dict, spatial: list) -> None:
    """Origin, spacing and direction from ``space directions``/``space origin`` (in LPS), else ``spacings``."""
    to_lps = _NRRD_SPACES.get(str(header.get("space", "")).strip().lower(), np.eye(3))
    origin = header.get("space origin")
    origin = np.zeros(3) if origin is None or len(origin) != 3 else np.asarray(origin, dtype=float)
    directions = header.get("space directions")
    if directions is not None and all(len(directions[axis]) == 3 for axis in spatial):
        columns = np.array([np.asarray(directions[axis], dtype=float) for axis in spatial]).T
        split = _split(columns)
        if split is not None:
            direction, spacing = split
            _set_geometry(image, to_lps @ origin, spacing, to_lps @ direction)
            return
        warnings.warn(f"'{path}': the space directions are not perpendicular; the orientation "
                      "is ignored (their lengths are the spacing)", stacklevel=caller_level())
        _set_geometry(image, to_lps @ origin, np.linalg.norm(columns, axis=0), np.eye(3))
        return
    spacings = header.get("spacings")
    spacing = [1.0, 1.0, 1.0]
    if spacings is not None:
        spacing = [float(spacings[a]) if np.isfinite(spacings[a]) and spacings[a] > 0 else 1.0 for a in spatial]
    _set_geometry(image, to_lps @ origin, spacing, np.eye(3))


#: Relative spread of a rectilinear grid's steps (largest - smallest, over the mean) still read as even, beyond
#: the rounding of float32 coordinates (8 float32 epsilons of the largest coordinate: a 0.1-degree latitude grid
#: stored as float32 spreads its steps by 8e-5 of a step).
EVEN_STEPS = 1e-5


def as_image_data(data):
    """``data`` as image data the ray caster draws right: right-handed, and a rectilinear grid evenly spaced.

    A composite data set (pyvista's ``MultiBlock``, a ``.vtm`` or ``.vtpd``
    file) is the one volume it holds (:func:`mipcast.io.composite.one_image`:
    its only data set, or image pieces of one grid joined; else a
    ``TypeError`` naming the fix).  Image data with a left-handed direction matrix becomes its
    :func:`right_handed` copy.  pyvista's ``RectilinearGrid`` (a netCDF or
    xarray grid of latitudes, longitudes and levels, a simulation's output)
    is image data when its steps along each axis are equal (within
    :data:`EVEN_STEPS`): the copy shares its point and cell arrays; a
    decreasing axis becomes a flipped direction (an odd number of them a
    reflection, made right-handed, which copies the arrays).  Uneven steps
    raise with the fix (resample first); anything else is returned as it is
    (the checks name what cannot be drawn).  ``data`` is not modified.

    Raises
    ------
    TypeError
        For a rectilinear grid whose steps along an axis differ; a composite
        data set of several data sets that are not pieces of one image.

    Examples
    --------
    >>> import numpy as np
    >>> from vtkmodules.util.numpy_support import numpy_to_vtk
    >>> grid = vtkRectilinearGrid()
    >>> grid.SetDimensions(3, 2, 2)
    >>> for axis, values in zip("XYZ", ([0.0, 0.5, 1.0], [4.0, 2.0], [1.0, 3.0])):
    ...     getattr(grid, f"Set{axis}Coordinates")(numpy_to_vtk(np.array(values), deep=True))
    >>> image = as_image_data(grid)
    >>> image.GetOrigin(), image.GetSpacing(), image.GetDirectionMatrix().GetElement(1, 1)
    ((0.0, 4.0, 3.0), (0.5, 2.0, 2.0), -1.0)
    """
    if isinstance(data, vtkCompositeDataSet):
        data = one_image(data)
    if isinstance(data, vtkImageData):
        return right_handed(data)
    if not isinstance(data, vtkRectilinearGrid):
        return data
    origin, spacing, signs = [], [], []
    for axis, coordinates in zip("xyz", (data.GetXCoordinates(), data.GetYCoordinates(), data.GetZCoordinates())):
        values = vtk_to_numpy(coordinates).astype(np.float64) if coordinates is not None else np.zeros(1)
        steps = np.diff(values)
        step = float(steps.mean()) if steps.size else 1.0
        rounding = 8.0 * float(np.finfo(np.float32).eps) * float(np.abs(values).max()) if values.size else 0.0
        if steps.size and (step == 0.0 or np.ptp(steps) > EVEN_STEPS * abs(step) + rounding
                           or np.any(steps * step <= 0)):
            raise TypeError(
                f"the rectilinear grid's {axis} coordinates are not evenly spaced (steps {steps.min():g} to "
                f"{steps.max():g}); resample it to image data first (pyvista: grid.sample(pyvista.ImageData(...)) "
                "or vtkResampleToImage)")
        origin.append(float(values[0]) if values.size else 0.0)
        spacing.append(abs(step))
        signs.append(1.0 if step > 0 else -1.0)
    image = vtkImageData()
    image.SetDimensions(data.GetDimensions())
    image.SetOrigin(origin)
    image.SetSpacing(spacing)
    image.SetDirectionMatrix(signs[0], 0.0, 0.0, 0.0, signs[1], 0.0, 0.0, 0.0, signs[2])
    image.GetPointData().ShallowCopy(data.GetPointData())
    image.GetCellData().ShallowCopy(data.GetCellData())
    return right_handed(image)  # an odd number of decreasing axes: a reflection, reversed (copies)


def with_scalars(image, scalars=None, preference: str = "point"):
    """``image``, or a shallow copy of it whose active point scalars are ``scalars``.

    A cell array (and no point array) of that name: the image of the cell
    centres carrying it (:func:`mipcast.core.prepare.cell_centres`), which is
    how a cell array is drawn.  ``scalars`` may also be the values
    themselves, as pyvista's ``add_volume`` takes them: an array of one value
    (or one row of components) per point, in point order (x fastest), or per
    cell; it becomes the copy's array ``"Data"`` (pyvista's name).

    The copy shares the arrays; the image given is not modified.  It is a
    snapshot of the image's array *list*: values changed in place show, but
    an array replaced or added later does not (render or add again).

    Parameters
    ----------
    image : vtkImageData
        The volume (a pyvista.ImageData is one).
    scalars : str or array_like, optional
        Name of a point (or cell) array of ``image``, or the values, shape
        ``(n,)`` or ``(n, components)`` with ``n`` the number of points or
        of cells; ``None`` returns ``image`` itself.
    preference : {"point", "cell"}, default: "point"
        Which array a name means when ``image`` has a point array and a cell
        array of that name (pyvista's ``preference``).

    Raises
    ------
    ValueError
        If ``image`` has no numeric point or cell array of that name (the
        message lists the point arrays), or the values' shape fits neither
        the points nor the cells.
    TypeError
        If the values are not numbers.

    Examples
    --------
    >>> from vtkmodules.util.numpy_support import numpy_to_vtk
    >>> image = vtkImageData()
    >>> image.SetDimensions(4, 4, 4)
    >>> for name in ("a", "b"):
    ...     array = numpy_to_vtk(np.zeros(64))
    ...     array.SetName(name)
    ...     index = image.GetPointData().AddArray(array)
    >>> image.GetPointData().SetActiveScalars("a")
    0
    >>> with_scalars(image, "b").GetPointData().GetScalars().GetName(), image.GetPointData().GetScalars().GetName()
    ('b', 'a')
    >>> with_scalars(image, np.arange(64.0)).GetPointData().GetScalars().GetName()
    'Data'
    """
    if scalars is None:
        return image
    if preference not in ("point", "cell"):
        raise ValueError(f"preference must be 'point' or 'cell', got {preference!r}")
    if not isinstance(scalars, str):
        return _with_values(image, scalars)
    points, cells = image.GetPointData(), image.GetCellData()
    if cells.GetArray(scalars) is not None and (points.GetArray(scalars) is None or preference == "cell"):
        return cell_centres(image, scalars)
    if points.GetArray(scalars) is None:
        names = [points.GetArrayName(i) for i in range(points.GetNumberOfArrays()) if points.GetArray(i)]
        if points.GetAbstractArray(scalars) is not None:
            fix = f"it is not numeric; numeric point arrays: {names}"
        else:
            fix = f"point arrays: {names}"
        raise ValueError(f"scalars {scalars!r} is not a numeric point array of the image; {fix}")
    copy = image.NewInstance()
    copy.ShallowCopy(image)
    copy.GetPointData().SetActiveScalars(scalars)
    return copy


def vtk_values(values) -> np.ndarray:
    """``values`` as VTK can hold them: masked entries NaN, complex numbers as (real, imaginary) components,
    float16 as float32, long double as float64, in the machine's byte order.

    A numpy masked array (netCDF4 and h5py-based readers return one where a
    variable has a fill value: land in an ocean model, no-data cells) would
    lose its mask in ``np.asarray`` and draw the fill value; its masked
    entries become missing data instead (NaN, in a float32 copy for 8/16-bit
    integers and float16/32, float64 otherwise; the caller's array is not
    modified).  Complex values (an MR reconstruction before its magnitude is
    taken) get a last axis of two components, real and imaginary, as
    pyvista stores them: their magnitude is drawn by default (``component=0``
    the real part).  Big-endian arrays (FITS files through astropy, some raw
    scanner dumps) are copied in the machine's byte order: ``pyvista.wrap``
    byte-swaps them in place, which corrupted the caller's array.  Other
    arrays are returned unchanged.

    Examples
    --------
    >>> vtk_values(np.zeros(3, np.float16)).dtype.name, vtk_values(np.zeros(3, np.int16)).dtype.name
    ('float32', 'int16')
    >>> vtk_values(np.ma.masked_array([1, 2, 3], mask=[0, 1, 0], dtype=np.int16))
    array([ 1., nan,  3.], dtype=float32)
    >>> vtk_values(np.array([3 + 4j], np.complex64))
    array([[3., 4.]], dtype=float32)
    >>> vtk_values(np.arange(3, dtype=">i4")).dtype.isnative
    True
    """
    mask = np.ma.getmaskarray(values) if isinstance(values, np.ma.MaskedArray) else None
    values = np.asarray(values.data if mask is not None else values)
    if not values.dtype.isnative:
        values = values.astype(values.dtype.newbyteorder("="))
    if values.dtype.kind == "c":
        values = np.stack([values.real, values.imag], axis=-1)
        mask = None if mask is None else np.repeat(mask[..., None], 2, axis=-1)
    if values.dtype.kind == "f" and values.dtype.itemsize == 2:
        values = values.astype(np.float32)
    if values.dtype.kind == "f" and values.dtype.itemsize > 8:
        values = values.astype(np.float64)
    if mask is None or not mask.any():
        return values
    if values.dtype.kind not in "iufb":
        raise TypeError(f"values must be numbers, got a masked array of dtype {values.dtype}")
    small = values.dtype.itemsize <= (4 if values.dtype.kind == "f" else 2)
    values = values.astype(np.float32 if small else np.float64)
    values[mask] = np.nan
    return values


def _with_values(image, values):
    """A shallow copy of ``image`` carrying ``values`` (one per point or per cell) as its active scalars "Data"."""
    values = vtk_values(values)
    if values.dtype.kind not in "iufb":
        raise TypeError(f"scalars given as values must be numbers, got an array of dtype {values.dtype}")
    points, cells = image.GetNumberOfPoints(), image.GetNumberOfCells()
    if values.ndim not in (1, 2) or values.shape[0] not in (points, cells):
        raise ValueError(
            f"scalars given as values must have shape (n,) or (n, components) with n the number of points "
            f"({points}) or cells ({cells}) of the image, got shape {values.shape}; for an array indexed "
            "[x, y, z] pass values.ravel(order='F') (point order: x fastest)")
    array = numpy_to_vtk(np.ascontiguousarray(values if values.dtype.kind != "b" else values.astype(np.uint8)),
                         deep=True)
    array.SetName("Data")
    copy = image.NewInstance()
    copy.ShallowCopy(image)
    if values.shape[0] == points:
        copy.GetPointData().AddArray(array)
        copy.GetPointData().SetActiveScalars("Data")
        return copy
    copy.GetCellData().AddArray(array)
    return cell_centres(copy, "Data")

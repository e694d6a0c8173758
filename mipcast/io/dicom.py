"""Read a DICOM series (a folder of slices, or one multi-frame file) as a volume.

pydicom is imported inside the functions only, so ``import mipcast`` works
without it (e.g. in ParaView's Python).  pyvista is imported lazily too:
:func:`read_dicom` returns a ``pyvista.ImageData`` when pyvista is
installed, else a plain ``vtkImageData`` with the same content.

Geometry follows DICOM's patient coordinate system (LPS: +x towards the
patient's left, +y posterior, +z superior, in mm):

- VTK index ``i`` runs along the pixel columns (along the *row* direction
  cosine, ``ImageOrientationPatient[:3]``), ``j`` along the rows (column
  direction cosine, ``ImageOrientationPatient[3:]``) and ``k`` along the
  slice normal (row cosine x column cosine), so the direction matrix has
  the columns (row cosine, column cosine, normal).
- Pixel ``pixel_array[r, c]`` of the ``k``-th slice (sorted by position
  along the normal) is point ``(i, j, k) = (c, r, k)``; the scalars are the
  volume ``(nz, ny, nx) = (slices, Rows, Columns)`` flattened in C order.
- Spacing is ``(PixelSpacing[1], PixelSpacing[0], slice step)``: DICOM's
  PixelSpacing lists the row spacing (between rows) first.  The slice step
  comes from the slice positions (a least-squares fit), never from
  SliceThickness (except for a Siemens mosaic, whose tiles have one
  position: SpacingBetweenSlices, else SliceThickness, as nibabel does).

Every problem with the input is raised as :class:`DicomError`, a ValueError
(FileNotFoundError for a missing path).  See docs/dicom.md.
"""
from __future__ import annotations

import contextlib
import math
import os
import sys
import warnings
from collections import Counter, abc
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from vtkmodules.util.numpy_support import get_vtk_array_type, numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDataArray, vtkStringArray
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.errors import InputError

PathLike = Union[str, "os.PathLike[str]"]

#: Name of the point-data array holding the rescaled values.
SCALARS_NAME = "values"
#: Name of the one-value string array in the field data holding the units.
UNITS_NAME = "units"
#: Names of the field-data arrays holding the series' own grey windows (its VOI LUT windows: WindowCenter /
#: WindowWidth, see :func:`_series_windows`): (low, high) in the values' units, two components a window, the
#: scanner's first window first; and each window's WindowCenterWidthExplanation (``""`` where it has none).
WINDOWS_NAME = "dicom_windows"
WINDOW_NAMES_NAME = "dicom_window_names"

# Tolerances (see _check_steps for how they are used).  Positions are fitted
# with a least-squares regular grid; the tolerances scale with the voxel.
ORIENTATION_TOL = 1e-3      # cosines: about 0.06 degrees
POSITION_TOL = 0.2          # a slice may sit up to 0.2 x the step off the fitted grid
WARN_TOL = 1e-3             # warn (once per volume) beyond 0.1 % of the step
DUPLICATE_FACTOR = 0.1      # a step < 0.1 x the median step is a duplicate position
GAP_FACTOR = 1.5            # a step > 1.5 x the median step is a missing slice
TILT_TOL_PIXELS = 0.1       # systematic lateral drift of slice origins, in pixels
MAX_TILT_DEG = 30.0         # a steady drift up to this angle is gantry tilt, corrected (CT gantries tilt to 30)
LATERAL_TOL_PIXELS = 0.5    # scatter of slice origins sideways to the normal, in pixels
#: Largest decoded volume in bytes (4 GiB); a header asking for more is refused
#: before anything is allocated.
MAX_BYTES = 4 * 2 ** 30
#: Largest ratio of decoded to stored bytes accepted for compressed pixel data.
MAX_COMPRESSION = 1000


def caller_level() -> int:
    """The ``stacklevel`` that points a warning at the first caller outside ``mipcast.io`` (the caller of
    ``read_dicom`` or ``read_volume``), for the function that calls ``warnings.warn``.

    Examples
    --------
    >>> caller_level() >= 1
    True
    """
    frame, level = sys._getframe(1), 1
    while frame is not None and os.path.dirname(os.path.abspath(frame.f_code.co_filename)) == _HERE:
        frame, level = frame.f_back, level + 1
    return level


_HERE = os.path.dirname(os.path.abspath(__file__))


class DicomError(InputError):
    """A DICOM input that cannot be read as a volume; the message says why and what to do.

    A subclass of :class:`mipcast.InputError` (itself a ValueError), so
    ``except ValueError`` keeps working.

    Examples
    --------
    >>> issubclass(DicomError, InputError), issubclass(DicomError, ValueError)
    (True, True)
    """


class DicomGeometryWarning(UserWarning):
    """Slice positions off a regular grid within the tolerance (issued once per volume)."""


class DicomSeriesWarning(UserWarning):
    """Images of the series left out of the volume (localizers stored in the series, copies of one image),
    named in the message."""


class DicomPaddingWarning(UserWarning):
    """Pixels of the series that hold its PixelPaddingValue (outside the scanned field): read as missing
    data, or kept as values where lossy compression moved them off the padding value (issued once per volume)."""


#: Transfer syntaxes that are (or may be) lossy, where a LossyImageCompression tag does not say.
LOSSY_SYNTAXES = {"1.2.840.10008.1.2.4.50", "1.2.840.10008.1.2.4.51", "1.2.840.10008.1.2.4.81",
                  "1.2.840.10008.1.2.4.91", "1.2.840.10008.1.2.4.203"}
#: What :func:`read_dicom` does with pixels that hold the PixelPaddingValue.
PADDING_CHOICES = ("missing", "keep")


# Suggested `pip install` per transfer syntax whose decoder can be missing.
_DECODER_PACKAGES = {
    "1.2.840.10008.1.2.4.50": "pylibjpeg pylibjpeg-libjpeg",   # JPEG baseline (Pillow works too)
    "1.2.840.10008.1.2.4.51": "pylibjpeg pylibjpeg-libjpeg",   # JPEG extended
    "1.2.840.10008.1.2.4.57": "pylibjpeg pylibjpeg-libjpeg",   # JPEG lossless
    "1.2.840.10008.1.2.4.70": "pylibjpeg pylibjpeg-libjpeg",   # JPEG lossless SV1
    "1.2.840.10008.1.2.4.80": "pylibjpeg pylibjpeg-libjpeg",   # JPEG-LS lossless
    "1.2.840.10008.1.2.4.81": "pylibjpeg pylibjpeg-libjpeg",   # JPEG-LS near-lossless
    "1.2.840.10008.1.2.4.90": "pylibjpeg pylibjpeg-openjpeg",  # JPEG 2000 lossless
    "1.2.840.10008.1.2.4.91": "pylibjpeg pylibjpeg-openjpeg",  # JPEG 2000
    "1.2.840.10008.1.2.4.201": "pylibjpeg pylibjpeg-openjpeg",  # HTJ2K lossless
    "1.2.840.10008.1.2.4.202": "pylibjpeg pylibjpeg-openjpeg",  # HTJ2K lossless RPCL
    "1.2.840.10008.1.2.4.203": "pylibjpeg pylibjpeg-openjpeg",  # HTJ2K
    "1.2.840.10008.1.2.5": "pylibjpeg pylibjpeg-rle",          # RLE (numpy decoder built in)
}
_ANY_DECODER = "pylibjpeg pylibjpeg-libjpeg pylibjpeg-openjpeg pylibjpeg-rle"


# ---------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------

def read_dicom(path: PathLike, series_uid: Optional[str] = None, padding: str = "missing"):
    """Read one DICOM series as a volume with its patient-space geometry.

    Parameters
    ----------
    path : str or os.PathLike
        A folder holding the files of a series (single-frame slices, or
        multi-frame files), or one DICOM file (a multi-frame volume such as
        RT Dose or an enhanced CT/MR, or a single slice).  File names and
        extensions do not matter; files that are not DICOM are skipped.
        Subfolders are not searched.
    series_uid : str, optional
        The SeriesInstanceUID to read when the folder holds several image
        series, or the ``"id"`` that :func:`list_series` gives a volume of
        a series that holds several (echoes, time points, acquisitions,
        stacks), e.g. ``"1.2.3.4#EchoNumbers=2"``.
    padding : {"missing", "keep"}
        What to do with the pixels that hold the series' PixelPaddingValue
        (from it up to PixelPaddingRangeLimit when given; stored values,
        before rescaling): the corners outside a CT's circular field of
        view, written as e.g. -2000 (-3024 HU).  ``"missing"`` (default)
        reads them as NaN, missing data that no projection, average or
        default window counts (the values become float32), with a
        :class:`DicomPaddingWarning` giving how many; ``"keep"`` keeps them
        as values, as most readers do.  Lossy compressed pixel data
        (LossyImageCompression "01", or a lossy transfer syntax without
        that tag) no longer holds the padding value exactly where it was
        written; it is kept, with a warning, whatever ``padding`` says.

    Returns
    -------
    pyvista.ImageData
        (a plain ``vtkImageData`` if pyvista is not installed) with:

        - point scalars ``"values"``: the stored values after
          RescaleSlope/RescaleIntercept (for RT Dose: DoseGridScaling).
          float32 if any slope or intercept is not an integer (or the stored
          values are floats, or padding is read as missing: NaN), else the first of int16/int32 that holds the
          range (uint32/float64 beyond that);
        - field data ``"units"``: one string -- ``"HU"`` for CT (or the
          RescaleType if it names something else), ``"Gy"`` or
          ``"relative"`` for RT Dose, the ``Units`` tag for PET (e.g.
          ``"BQML"``), ``""`` when DICOM does not say (e.g. MR);
        - field data ``"dicom_windows"`` and ``"dicom_window_names"`` where
          the series has grey windows of its own (WindowCenter /
          WindowWidth, several with WindowCenterWidthExplanation; an
          enhanced file's FrameVOILUTSequence): (low, high) a window in the
          values' units, as DICOM's VOILUTFunction maps them, the scanner's
          first window first, and their names.  A series whose slices have
          different windows (an MR scanner windows each) gets the windows most
          slices share, or one from the slices' median centre and width.
          ``window="dicom"`` (``--window dicom``, ``clim="dicom"``) draws
          with the first, ``"dicom:2"`` or ``"dicom:BONE"`` another
          (:func:`mipcast.core.windowing.dicom_windows`);
        - dimensions ``(Columns, Rows, slices)``, spacing
          ``(PixelSpacing[1], PixelSpacing[0], slice step)``, origin the
          ImagePositionPatient of the first slice along the normal, and the
          direction matrix with columns (row cosine, column cosine, normal).
          The slice step and origin are the least-squares regular grid
          through the slice positions; when a slice sits more than 0.1 % of
          the step off it (positions rounded in the headers), one
          :class:`DicomGeometryWarning` names the largest misplacement.
        - gantry tilt (the slice origins drifting steadily sideways, up to
          30 deg): each slice is shifted onto an untilted grid (linear
          between pixels; float32; the points no slice covers are NaN,
          missing data), with one :class:`DicomGeometryWarning` giving the
          angle;
        - missing slices (a step of m usual steps, m a whole number): their
          places hold missing data (NaN; float32), with one
          :class:`DicomGeometryWarning` naming the gaps;
        - a spacing that changes in zones (e.g. 1.25 mm, then 2.5 mm):
          resampled linearly along the normal onto a regular grid from the
          first to the last slice, no coarser than the finest zone (float32),
          with one :class:`DicomGeometryWarning` naming the zones;
        - localizer (scout) images that a scanner stored in the series of
          the volume (ImageType LOCALIZER), and copies of an image (files of
          one SOPInstanceUID: a folder copied or exported twice), are left
          out, with a :class:`DicomSeriesWarning` naming the files;
        - Siemens MOSAIC files are unpacked into their slices; enhanced
          multi-frame files use their shared and per-frame functional
          groups (position, orientation, pixel spacing, rescale).

        A single slice gives an image one point thick: it is returned, but
        :func:`mipcast.io.read_volume` and the renderers refuse it.
        MONOCHROME1 images are returned as stored (not inverted).

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    DicomError
        (a ValueError) with what is wrong and how to fix it: no DICOM files;
        no images among them (only non-image objects such as RT structure
        sets); several image series, or several volumes in one series, and
        no ``series_uid``; an unknown ``series_uid``; a gap between slices
        that is no whole number of steps, large steps in a row that form no
        zones, or more missing slices than present ones; two slices at the
        same position; a slice
        more than 0.2 x the step off the least-squares grid (stacks with
        different spacing mixed); slices with different orientations, sizes
        or pixel spacings; a sideways drift of the slice origins steeper
        than a gantry tilts (30 deg) or origins scattered sideways by more
        than half a pixel;
        colour images; images without ImagePositionPatient/
        ImageOrientationPatient; a mosaic without its image count;
        compressed pixel data without an installed decoder (the message
        names the package to install); a header describing more pixels than
        the file stores (or more than 4 GiB, or more than 1000:1 compressed),
        refused before anything is allocated; damaged files (whatever pydicom
        or a decoder raised is chained as ``__cause__``).
    ImportError
        If pydicom is not installed.

    Examples
    --------
    A CT series of 5 slices (files named by number, stored top-down):

    >>> import os
    >>> from pydicom.data import get_testdata_file
    >>> folder = os.path.dirname(get_testdata_file("dicomdirtests/98892001/CT5N/2062"))
    >>> ct = read_dicom(folder)
    >>> ct.dimensions, ct.spacing
    ((16, 16, 5), (0.488281, 0.488281, 2.5))
    >>> ct.origin  # the most inferior slice (lowest z) comes first
    (-72.199997, -143.0, -1.2375)
    >>> str(ct.field_data["units"][0]), ct.point_data["values"].dtype.name
    ('HU', 'int16')

    A multi-frame RT Dose grid (offsets from GridFrameOffsetVector):

    >>> dose = read_dicom(get_testdata_file("rtdose.dcm"))
    >>> dose.dimensions, dose.spacing, dose.point_data["values"].dtype.name
    ((10, 10, 15), (10.0, 10.0, 5.0), 'float32')

    One slice (returned; rendering needs at least two):

    >>> read_dicom(get_testdata_file("CT_small.dcm")).dimensions
    (128, 128, 1)

    Compressed pixel data (JPEG, JPEG-LS, JPEG 2000, RLE) decodes through
    pydicom's plugins (pylibjpeg and its libjpeg, openjpeg and rle
    packages are dependencies):

    >>> read_dicom(get_testdata_file("MR_small_jpeg_ls_lossless.dcm")).dimensions
    (64, 64, 1)
    """
    if padding not in PADDING_CHOICES:
        raise ValueError(f"padding must be one of {PADDING_CHOICES}, got {padding!r}")
    pydicom = _import_pydicom()
    path = Path(path)
    with _damaged_as_dicom_error(path):
        image = _read(path, series_uid, pydicom, padding)
    try:
        import pyvista
    except ImportError:  # e.g. ParaView's Python: plain VTK is enough
        return image
    return pyvista.wrap(image)


def _read(path: Path, series_uid: Optional[str], pydicom, padding: str = "missing") -> vtkImageData:
    datasets = _scan(path, pydicom)
    images = [(file, ds) for file, ds in datasets if _has_pixels(ds)]
    if not images:
        kinds = sorted({str(ds.get("Modality", "?")) for _, ds in datasets})
        raise DicomError(
            f"'{path}' holds {len(datasets)} DICOM file(s) but none with pixel data "
            f"(modalities: {', '.join(kinds)}); these are non-image objects (structure "
            "sets, plans, reports, DICOMDIR ...): point to the folder holding the image slices")
    series: Dict[str, list] = {}
    for file, ds in images:
        series.setdefault(_series_uid(ds), []).append((file, ds))
    uid, _, volume = str(series_uid).partition("#") if series_uid is not None else (None, "", "")
    if uid is None:
        if len(series) > 1:
            raise DicomError(
                f"'{path}' holds {len(series)} image series; choose one with "
                "series_uid=... (read_dicom(path, series_uid=...) or "
                "read_volume(path, series_uid=...)), or move each series into its own "
                f"folder:\n{_listing(images)}")
        uid = next(iter(series))
    elif uid not in series:
        raise DicomError(
            f"no image series with SeriesInstanceUID {uid!r} in '{path}'; "
            f"the image series there are:\n{_listing(images)}")
    chosen = _unique_instances(series[uid], f"series {uid} in '{path}'")
    frames = []
    for file, ds in chosen:
        frames.extend(_frames_of(file, ds))
    volumes = _split(_without_localizers(frames, f"series {uid} in '{path}'"))
    if volume not in volumes:
        if volume or len(volumes) > 1:
            ids = ", ".join(repr(f"{uid}#{key}") for key in volumes if key)
            raise DicomError(
                f"series {uid} in '{path}' holds {len(volumes)} volumes (several images per "
                f"slice position or several orientations, told apart by {next(iter(volumes)).split('=')[0]}); choose "
                f"one with series_uid= one of {ids}" if len(volumes) > 1 else
                f"series {uid} in '{path}' is one volume; {series_uid!r} names none: pass "
                f"series_uid={uid!r}")
        volume = ""
    frames = volumes[volume]
    chosen = [(file, ds) for file, ds in chosen if any(f.file == file for f in frames)]
    return _assemble(frames, chosen, pydicom, padding)


def list_series(path: PathLike) -> List[Dict[str, Any]]:
    """List the DICOM series in a folder (or the one series of a file).

    Parameters
    ----------
    path : str or os.PathLike
        A folder (subfolders are not searched) or a DICOM file.

    Returns
    -------
    list of dict
        One dict per SeriesInstanceUID, ordered by SeriesNumber, with keys
        ``"uid"``, ``"modality"``, ``"description"`` (SeriesDescription, may
        be ``""``), ``"number"`` (SeriesNumber or ``None``), ``"n_files"``
        and ``"n_images"`` (files with pixel data; series with 0 images, such
        as structure sets, cannot be read as volumes), ``"n_slices"`` (2D
        images, mosaic tiles and frames counted; ``None`` if they are not
        slices of a volume), ``"volume"`` and ``"id"``.  A series holding
        several volumes (several images per position: echoes, time points,
        acquisitions; or several stacks) gives one dict per volume, with
        ``"volume"`` naming what tells it apart (e.g. ``"EchoNumbers=2"``)
        and ``"id"`` = ``"uid#volume"`` to pass as ``series_uid``; else
        ``"volume"`` is ``""`` and ``"id"`` is the uid.

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        If there are no DICOM files.

    Examples
    --------
    >>> import os
    >>> from pydicom.data import get_testdata_file
    >>> folder = os.path.dirname(get_testdata_file("dicomdirtests/98892001/CT5N/2062"))
    >>> [(s["modality"], s["n_files"], s["n_images"], s["n_slices"]) for s in list_series(folder)]
    [('CT', 5, 5, 5)]
    """
    pydicom = _import_pydicom()
    with _damaged_as_dicom_error(Path(path)):
        return _volume_entries(_scan(Path(path), pydicom))


@contextlib.contextmanager
def _damaged_as_dicom_error(path: Path):
    """Report pydicom's and numpy's errors on damaged files as one :class:`DicomError`.

    Damaged files make pydicom fail lazily, when a value is first used, with
    whatever the bytes trigger (struct.error, KeyError, TypeError,
    UnicodeDecodeError, OverflowError ...); callers see one documented class.
    """
    try:
        yield
    except (DicomError, FileNotFoundError, MemoryError):
        raise
    except Exception as error:
        raise DicomError(
            f"'{path}' holds damaged DICOM data that could not be read "
            f"({type(error).__name__}: {error}); re-export or re-copy the files "
            "(or remove the damaged one)") from error


# ---------------------------------------------------------------------------
# finding and grouping files
# ---------------------------------------------------------------------------

def _import_pydicom():
    try:
        import pydicom
    except ImportError:
        raise ImportError(
            "reading DICOM needs pydicom: pip install pydicom "
            "(Debian/ParaView: apt-get install python3-pydicom)") from None
    return pydicom


def _scan(path: Path, pydicom) -> list:
    """Return [(file, dataset)] for the DICOM files at ``path`` (pixels deferred)."""
    if not path.exists():
        raise FileNotFoundError(f"no such DICOM file or folder: '{path}'")
    if path.is_file():
        ds = _read_header(path, pydicom)
        if ds is None:
            raise DicomError(
                f"'{path}' is not a DICOM file (no 'DICM' marker and no DICOM data set at "
                "its start); pass a DICOM file or the folder holding the series")
        return [(path, ds)]
    files = sorted(p for p in path.iterdir() if p.is_file() and not p.name.startswith("."))
    found = []
    for file in files:
        ds = _read_header(file, pydicom)
        if ds is not None:
            found.append((file, ds))
    if not found:
        subfolders = sorted(p.name for p in path.iterdir() if p.is_dir())
        hint = (f"; it has subfolders ({', '.join(subfolders[:5])}"
                f"{', ...' if len(subfolders) > 5 else ''}) -- subfolders are not searched, "
                "pass the folder that holds the slices" if subfolders else
                "; pass the folder that holds the slices of one series")
        raise DicomError(f"no DICOM files in '{path}' ({len(files)} file(s) checked){hint}")
    return found


class _BoundedFile:
    """A binary file whose reads stop at its end, even when asked for more.

    pydicom reads a value with ``read(length)`` where ``length`` comes from the
    file; Python allocates ``length`` bytes first, so a corrupt length of
    0xFFFFFFF0 would allocate 4 GiB.  Reads through this class never ask for
    more than what is left.  pydicom reopens files with the same class for its
    deferred reads (pixel data), so those are bounded too.
    """

    def __init__(self, path, mode: str = "rb"):
        self._file = open(path, "rb")
        self.name = str(path)
        self._size = os.fstat(self._file.fileno()).st_size

    def read(self, size: Optional[int] = -1) -> bytes:
        if size is None or size < 0:
            return self._file.read()
        return self._file.read(min(size, max(0, self._size - self._file.tell())))

    def seek(self, offset: int, whence: int = 0) -> int:
        return self._file.seek(offset, whence)

    def tell(self) -> int:
        return self._file.tell()

    def close(self) -> None:
        self._file.close()

    @property
    def closed(self) -> bool:
        return self._file.closed

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _dcmread(file: Path, pydicom, **options):
    with _BoundedFile(file) as handle:
        return pydicom.dcmread(handle, defer_size="16 KB", **options)


def _read_header(file: Path, pydicom):
    """The data set of ``file`` with its large values (pixels) deferred, or None."""
    from pydicom.errors import InvalidDicomError

    try:
        return _dcmread(file, pydicom)
    except InvalidDicomError:
        pass
    except MemoryError:
        raise
    except Exception as error:  # a DICOM file that does not parse
        raise DicomError(
            f"'{file}' is a DICOM file but could not be read ({error}); remove or "
            "re-export it") from error
    # Old files without the 128-byte preamble and 'DICM': accept only if they
    # start like a data set (group 0x0002 or 0x0008, little endian) and parse.
    with open(file, "rb") as handle:
        head = handle.read(4)
    if head[:2] not in (b"\x02\x00", b"\x08\x00"):
        return None
    try:
        ds = _dcmread(file, pydicom, force=True)
        return ds if "SOPClassUID" in ds else None
    except Exception:
        return None


def _has_pixels(ds) -> bool:
    return any(k in ds for k in ("PixelData", "FloatPixelData", "DoubleFloatPixelData"))


def _series_uid(ds) -> str:
    return str(ds.get("SeriesInstanceUID", "") or "")


def _summaries(datasets) -> List[Dict[str, Any]]:
    table: Dict[str, Dict[str, Any]] = {}
    for _, ds in datasets:
        uid = _series_uid(ds)
        if uid not in table:
            number = ds.get("SeriesNumber", None)
            table[uid] = {
                "uid": uid,
                "modality": str(ds.get("Modality", "") or ""),
                "description": str(ds.get("SeriesDescription", "") or ""),
                "number": int(number) if number not in (None, "") else None,
                "n_files": 0,
                "n_images": 0,
            }
        table[uid]["n_files"] += 1
        table[uid]["n_images"] += int(_has_pixels(ds))
    return sorted(table.values(), key=lambda s: (s["number"] is None, s["number"] or 0, s["uid"]))


def _volume_entries(datasets) -> List[Dict[str, Any]]:
    """:func:`_summaries`, with a series split into its volumes where it holds several."""
    entries = []
    for entry in _summaries(datasets):
        entry["id"], entry["volume"] = entry["uid"], ""
        files = _unique_instances([(file, ds) for file, ds in datasets
                                   if _series_uid(ds) == entry["uid"] and _has_pixels(ds)])
        try:
            frames = _without_localizers([frame for file, ds in files for frame in _frames_of(file, ds)])
            volumes = _split(frames) if frames else {"": []}
        except DicomError:  # not a stack of slices (e.g. secondary captures): one entry
            volumes = {"": None}
        for key, group in volumes.items():
            item = dict(entry)
            item["n_slices"] = len(group) if group is not None else None
            if key:
                item["id"], item["volume"] = f"{entry['uid']}#{key}", key
                names = {frame.file for frame in group}
                item["n_files"] = item["n_images"] = len(names)
            entries.append(item)
    return entries


def _listing(images) -> str:
    return "\n".join(f"  {_describe(entry)}" for entry in _volume_entries(images))


def _describe(entry: Dict[str, Any]) -> str:
    text = f"{entry.get('id') or entry['uid'] or '(no SeriesInstanceUID)'}: {entry['modality'] or '?'}"
    if entry["number"] is not None:
        text += f" #{entry['number']}"
    if entry["description"]:
        text += f" '{entry['description']}'"
    return text + f", {entry['n_files']} file(s)"


# ---------------------------------------------------------------------------
# frames: one 2D image each, with its own geometry and rescale
# ---------------------------------------------------------------------------

class _Frame:
    """One 2D image: where it is, how to scale it, where its pixels are."""

    __slots__ = ("file", "index", "position", "orientation", "pixel_spacing",
                 "slope", "intercept", "rescale_type", "tile", "labels")

    def __init__(self, file, index, position, orientation, pixel_spacing, slope, intercept,
                 rescale_type, tile=None):
        #: (first row, first column, rows, columns) of a mosaic tile, else None
        self.tile = tile
        #: attributes that can tell volumes of one series apart (see _split)
        self.labels: Dict[str, str] = {}
        self.file = file
        self.index = index
        self.position = position
        self.orientation = orientation
        self.pixel_spacing = pixel_spacing
        self.slope = slope
        self.intercept = intercept
        self.rescale_type = rescale_type

    @property
    def name(self) -> str:
        if self.tile is not None:
            return f"{self.file.name} mosaic tile {self.tile[4] + 1}"
        return self.file.name if self.index is None else f"{self.file.name} frame {self.index + 1}"

    def shape(self, ds) -> tuple:
        """(rows, columns) of this frame's image."""
        if self.tile is not None:
            return self.tile[2], self.tile[3]
        return int(ds.Rows), int(ds.Columns)

    def pixels(self, decoded: np.ndarray) -> np.ndarray:
        """This frame's pixels from the decoded (frames, rows, columns) of its file."""
        image = decoded[self.index or 0]
        if self.tile is None:
            return image
        r, c, rows, cols, _ = self.tile
        return image[r:r + rows, c:c + cols]


def _floats(value, count: int, what: str, where: str) -> np.ndarray:
    try:
        numbers = np.array([float(v) for v in value], dtype=float)
    except (TypeError, ValueError):
        numbers = np.array([])
    if numbers.shape != (count,) or not np.isfinite(numbers).all():
        raise DicomError(f"{where}: {what} is {value!r}, expected {count} numbers")
    return numbers


def _first_item(container, keyword):
    if container is None:
        return None
    sequence = container.get(keyword, None)
    return sequence[0] if sequence else None


# Attributes that tell the volumes of one series apart, tried in this order
# when a series has several images at one position (see _split).
SPLIT_KEYS = ("EchoNumbers", "TemporalPositionIdentifier", "TemporalPositionIndex", "StackID",
              "EffectiveEchoTime", "AcquisitionNumber", "TriggerTime", "ImageType",
              "orientation", "file")


def _frames_of(file: Path, ds) -> List[_Frame]:
    """The frames of one file, with their geometry, rescale and volume labels."""
    frames = _frames_unlabelled(file, ds)
    common = {}
    for keyword in ("EchoNumbers", "TemporalPositionIdentifier", "AcquisitionNumber",
                    "TriggerTime", "ImageType"):
        value = ds.get(keyword, None)
        if value not in (None, ""):
            common[keyword] = _label(value)
    per_frame = ds.get("PerFrameFunctionalGroupsSequence", None)
    for frame in frames:
        frame.labels = dict(common, file=file.name,
                            orientation=_fmt(np.round(frame.orientation, 3)))
        if per_frame is not None and frame.index is not None and frame.index < len(per_frame):
            content = _first_item(per_frame[frame.index], "FrameContentSequence")
            echo = _first_item(per_frame[frame.index], "MREchoSequence")
            for item, keyword in ((content, "StackID"), (content, "TemporalPositionIndex"),
                                  (echo, "EffectiveEchoTime")):
                value = item.get(keyword, None) if item is not None else None
                if value not in (None, ""):
                    frame.labels[keyword] = _label(value)
    return frames


def _split(frames: List[_Frame]) -> Dict[str, List[_Frame]]:
    """The volumes of one series: ``{"": frames}``, or ``{"Key=value": frames}``.

    A series is split only when it has several images at one position (or
    several orientations, or an enhanced multi-frame has several StackIDs), by the first of :data:`SPLIT_KEYS` whose groups
    are each one clean stack of at least two images.
    """
    stacks = {frame.labels.get("StackID") for frame in frames}
    if not _needs_split(frames) and (len(stacks) < 2 or None in stacks):
        return {"": frames}
    for key in SPLIT_KEYS:
        groups: Dict[Any, List[_Frame]] = {}
        for frame in frames:
            groups.setdefault(frame.labels.get(key), []).append(frame)
        if len(groups) < 2 or None in groups:
            continue
        if any(len(group) < 2 for group in groups.values()):  # not stacks: refuse later
            continue
        if any(_needs_split(group) for group in groups.values()):
            continue
        return {f"{key}={value}": groups[value] for value in sorted(groups, key=_natural)}
    return {"": frames}


def _unique_instances(files: list, where: Optional[str] = None) -> list:
    """``files`` ((path, dataset) pairs) with one file per SOPInstanceUID: copies of one image (a folder
    exported or copied twice) are one image; with ``where``, a warning names the copies left out."""
    seen: Dict[str, Path] = {}
    kept, copies = [], []
    for file, ds in sorted(files, key=lambda pair: (len(pair[0].name), str(pair[0]))):  # "IM1" before "IM1 (1)"
        uid = str(ds.get("SOPInstanceUID", "") or "")
        if uid in seen:
            copies.append(f"{file.name} (= {seen[uid].name})")
            continue
        if uid:
            seen[uid] = file
        kept.append((file, ds))
    if copies and where is not None:
        warnings.warn(f"{where}: skipped {len(copies)} {'copy' if len(copies) == 1 else 'copies'} of an image "
                      f"already read (the same SOPInstanceUID): {', '.join(copies[:5])}"
                      f"{' ...' if len(copies) > 5 else ''}", DicomSeriesWarning, stacklevel=caller_level())
    return kept


def _without_localizers(frames: List[_Frame], where: Optional[str] = None) -> List[_Frame]:
    """``frames`` less the localizer (scout) images some scanners store in the series of the volume
    (ImageType LOCALIZER); with ``where``, a warning names them.  A series of localizers only, or
    with fewer than two other images, is returned as it is."""
    def localizer(frame):
        return "LOCALIZER" in frame.labels.get("ImageType", "").upper().split("\\")

    kept = [frame for frame in frames if not localizer(frame)]
    if len(kept) == len(frames) or len(kept) < 2:
        return frames
    if where is not None:
        names = sorted({frame.file.name for frame in frames if localizer(frame)})
        warnings.warn(f"{where}: skipped {len(frames) - len(kept)} localizer image(s) (ImageType LOCALIZER): "
                      f"{', '.join(names[:5])}{' ...' if len(names) > 5 else ''}", DicomSeriesWarning,
                      stacklevel=caller_level())
    return kept


def _natural(value: str):
    try:
        return (0, float(value), value)
    except ValueError:
        return (1, 0.0, value)


def _needs_split(frames: List[_Frame]) -> bool:
    if len({frame.labels.get("orientation") for frame in frames}) > 1:
        return True
    if len(frames) < 2:
        return False
    orientation = frames[0].orientation
    normal = np.cross(orientation[:3], orientation[3:])
    along = np.sort([float(frame.position @ normal) for frame in frames])
    steps = np.diff(along)
    nonzero = steps[steps > 1e-6]
    median = float(np.median(nonzero)) if nonzero.size else 0.0
    return bool((steps <= max(1e-4, DUPLICATE_FACTOR * median)).any())


def _label(value) -> str:
    if isinstance(value, (list, tuple)) or type(value).__name__ == "MultiValue":
        return "\\".join(str(v) for v in value)
    return str(value)


def _frames_unlabelled(file: Path, ds) -> List[_Frame]:
    """The frames of one file, with per-frame geometry and rescale."""
    where = f"'{file}'"
    samples = int(ds.get("SamplesPerPixel", 1) or 1)
    if samples != 1:
        raise DicomError(
            f"{where} is a colour image ({samples} samples per pixel, "
            f"{ds.get('PhotometricInterpretation', '?')}); a MIP needs one value per voxel: "
            "use a greyscale series")
    frames = int(ds.get("NumberOfFrames", 1) or 1)
    top_slope = float(ds.get("RescaleSlope", 1) or 1)
    top_intercept = float(ds.get("RescaleIntercept", 0) or 0)
    top_type = str(ds.get("RescaleType", "") or "")
    if "DoseGridScaling" in ds:  # RT Dose: the scale lives here
        top_slope = float(ds.DoseGridScaling)

    per_frame = ds.get("PerFrameFunctionalGroupsSequence", None)
    shared = _first_item(ds, "SharedFunctionalGroupsSequence")
    if per_frame is not None or shared is not None:  # enhanced multi-frame
        if per_frame is not None and len(per_frame) != frames:
            raise DicomError(f"{where}: {len(per_frame)} per-frame functional groups for "
                             f"{frames} frames; the file is inconsistent")
        result = []
        for index in range(frames):
            own = per_frame[index] if per_frame is not None else None

            def item(keyword):
                found = _first_item(own, keyword)
                return found if found is not None else _first_item(shared, keyword)

            plane_position = item("PlanePositionSequence")
            plane_orientation = item("PlaneOrientationSequence")
            measures = item("PixelMeasuresSequence")
            transform = item("PixelValueTransformationSequence")
            position = (plane_position.get("ImagePositionPatient", None)
                        if plane_position is not None else ds.get("ImagePositionPatient", None))
            orientation = (plane_orientation.get("ImageOrientationPatient", None)
                           if plane_orientation is not None
                           else ds.get("ImageOrientationPatient", None))
            spacing = (measures.get("PixelSpacing", None) if measures is not None
                       else ds.get("PixelSpacing", None))
            slope, intercept, rescale_type = top_slope, top_intercept, top_type
            if transform is not None:
                slope = float(transform.get("RescaleSlope", slope) or slope)
                intercept = float(transform.get("RescaleIntercept", intercept) or intercept)
                rescale_type = str(transform.get("RescaleType", rescale_type) or rescale_type)
            frame_where = f"{where} frame {index + 1}"
            result.append(_frame(file, index, position, orientation, spacing, slope, intercept,
                                 rescale_type, frame_where, ds))
        return result

    position = ds.get("ImagePositionPatient", None)
    orientation = ds.get("ImageOrientationPatient", None)
    spacing = ds.get("PixelSpacing", None)
    if frames == 1 and _is_mosaic(ds):
        base = _frame(file, None, position, orientation, spacing, top_slope, top_intercept,
                      top_type, where, ds)
        return _mosaic_frames(file, ds, base, where)
    if frames == 1:
        return [_frame(file, None, position, orientation, spacing, top_slope, top_intercept,
                       top_type, where, ds)]
    offsets = ds.get("GridFrameOffsetVector", None)
    if offsets is None:
        raise DicomError(
            f"{where} has {frames} frames but no per-frame positions (no "
            "PerFrameFunctionalGroupsSequence and no GridFrameOffsetVector): mipcast cannot "
            "tell where the frames are; convert it to a slice series or an enhanced "
            "multi-frame object first")
    offsets = _floats(offsets, frames, "GridFrameOffsetVector", where)
    base = _frame(file, 0, position, orientation, spacing, top_slope, top_intercept, top_type,
                  where, ds)
    row, col = base.orientation[:3], base.orientation[3:]
    normal = np.cross(row, col)
    normal /= np.linalg.norm(normal)
    if offsets[0] != 0.0:
        # Absolute form (DICOM C.8.8.3.2): offsets are coordinates along the
        # normal, the first one being that of ImagePositionPatient.
        offsets = offsets - float(base.position @ normal)
    return [_Frame(file, index, base.position + offset * normal, base.orientation,
                   base.pixel_spacing, top_slope, top_intercept, top_type)
            for index, offset in enumerate(offsets)]


def _is_mosaic(ds) -> bool:
    """A Siemens mosaic: ImageType says MOSAIC (as dcm2niix and nibabel check)."""
    image_type = ds.get("ImageType", None) or []
    if isinstance(image_type, str):
        image_type = [image_type]
    return any(str(v).upper() == "MOSAIC" for v in image_type)


def _nibabel_nicom():
    """nibabel's CSA reader and DICOM wrappers, without its 'experimental' import warning."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="The DICOM readers are highly experimental")
        from nibabel.nicom import csareader, dicomwrappers
    return csareader, dicomwrappers


def _csa_image_header(ds, where):
    """The parsed Siemens CSA image header of ``ds`` (nibabel.nicom.csareader), or None."""
    if (0x0029, 0x0010) not in ds:
        return None
    try:
        csareader, _ = _nibabel_nicom()
    except ImportError:
        raise DicomError(f"{where} is a Siemens mosaic; reading its CSA header needs nibabel: "
                         "pip install nibabel") from None
    try:
        return csareader.get_csa_header(ds, "image")
    except Exception as error:  # CSAReadError, struct.error ... on a damaged header
        raise DicomError(f"{where}: the Siemens CSA image header (0029,1010) is damaged "
                         f"({error}); re-export the series from the scanner") from error


def _mosaic_count(ds, where) -> Optional[int]:
    """NumberOfImagesInMosaic from the CSA header, else the private tag (0019,100A)."""
    csa = _csa_image_header(ds, where)
    count = None
    if csa is not None:
        count = _nibabel_nicom()[0].get_n_mosaic(csa)
    if count in (None, "", 0):
        try:
            block = ds.private_block(0x0019, "SIEMENS MR HEADER")
            value = block[0x0A].value if 0x0A in block else None
        except (KeyError, ValueError):
            value = None
        if isinstance(value, bytes) and len(value) in (2, 4):  # implicit VR: raw little endian
            value = int.from_bytes(value, "little")
        count = value
    try:
        return int(count) if count not in (None, "") else None
    except (TypeError, ValueError):
        return None


def _mosaic_frames(file, ds, base: _Frame, where) -> List[_Frame]:
    """The tiles of a Siemens mosaic as frames, with nibabel's mosaic geometry."""
    count = _mosaic_count(ds, where)
    if count is None or not 1 <= count <= 4096:
        raise DicomError(
            f"{where} is a Siemens mosaic (ImageType MOSAIC) but its number of images "
            f"(CSA NumberOfImagesInMosaic or (0019,100A)) is {count!r}; without it the tiles "
            "cannot be unpacked: convert the series with dcm2niix")
    size = int(math.ceil(math.sqrt(count)))
    rows, cols = int(ds.Rows), int(ds.Columns)
    if rows % size or cols % size:
        raise DicomError(f"{where}: a mosaic of {count} images ({size} x {size} tiles) cannot "
                         f"be {rows} x {cols} pixels; the header is inconsistent")
    csareader, dicomwrappers = _nibabel_nicom()
    csa = _csa_image_header(ds, where) or {}
    wrapper = dicomwrappers.MosaicWrapper(ds, csa, count)
    try:
        normal = np.asarray(wrapper.slice_normal, dtype=float)
        first = np.asarray(wrapper.image_position, dtype=float)
    except (AssertionError, TypeError, ValueError) as error:
        csa_normal = csareader.get_slice_normal(csa) if csa else None
        raise DicomError(
            f"{where}: the mosaic's CSA SliceNormalVector {csa_normal} is not the normal of "
            f"ImageOrientationPatient {_fmt(base.orientation)}; the header is inconsistent"
        ) from error
    step = None
    for keyword in ("SpacingBetweenSlices", "SliceThickness"):
        value = ds.get(keyword, None)
        if value not in (None, "") and float(value) > 0:
            step = float(value)
            break
    if step is None:
        raise DicomError(f"{where}: a mosaic without SpacingBetweenSlices or SliceThickness; "
                         "the slice step is unknown")
    tile_rows, tile_cols = rows // size, cols // size
    return [_Frame(file, None, first + k * step * normal, base.orientation, base.pixel_spacing,
                   base.slope, base.intercept, base.rescale_type,
                   ((k // size) * tile_rows, (k % size) * tile_cols, tile_rows, tile_cols, k))
            for k in range(count)]


def _frame(file, index, position, orientation, spacing, slope, intercept, rescale_type, where,
           ds) -> _Frame:
    if position is None or orientation is None:
        kind = f"{ds.get('Modality', '?')} {getattr(ds.get('SOPClassUID', None), 'name', '')}"
        raise DicomError(
            f"{where} ({kind.strip()}) has no ImagePositionPatient/ImageOrientationPatient: it "
            "is not a slice of a 3D volume (a projection, scout or secondary capture?); "
            "mipcast needs cross-sectional images (CT, MR, PET, RT dose ...)")
    if spacing is None:
        raise DicomError(f"{where} has no PixelSpacing, so the voxel size is unknown; "
                         "add it to the files (e.g. with pydicom) before reading")
    pixel_spacing = _floats(spacing, 2, "PixelSpacing", where)
    if not (pixel_spacing > 0).all():
        raise DicomError(f"{where}: PixelSpacing {list(pixel_spacing)} must be > 0")
    return _Frame(file, index, _floats(position, 3, "ImagePositionPatient", where),
                  _floats(orientation, 6, "ImageOrientationPatient", where), pixel_spacing,
                  float(slope), float(intercept), rescale_type)


# ---------------------------------------------------------------------------
# decoding
# ---------------------------------------------------------------------------

def _decoder_problem(ds) -> Optional[str]:
    """Why the pixel data of ``ds`` cannot be decoded here, or None."""
    meta = getattr(ds, "file_meta", None)
    syntax = meta.get("TransferSyntaxUID", None) if meta is not None else None
    if syntax is None or not syntax.is_compressed:
        return None
    try:
        from pydicom.pixels import get_decoder  # pydicom >= 3
    except ImportError:  # pydicom 2.x: decoding errors are reported when they happen
        return None
    try:
        decoder = get_decoder(syntax)
    except NotImplementedError:
        return (f"pydicom has no decoder at all for its transfer syntax {syntax.name} "
                f"({syntax}); convert the files to an uncompressed syntax first (e.g. "
                "`gdcmconv --raw` or `dcmdjpeg`)")
    if decoder.is_available:
        return None
    return _missing_decoder_text(syntax, list(decoder.missing_dependencies))


def _missing_decoder_text(syntax, missing: Sequence[str]) -> str:
    package = _DECODER_PACKAGES.get(str(syntax), _ANY_DECODER)
    text = (f"its pixel data is compressed with {syntax.name} ({syntax}) and no decoder for "
            f"it is installed: pip install {package}")
    if missing:
        text += f" (pydicom's options: {'; '.join(missing)})"
    return text


def _expected_bytes(ds) -> int:
    """Bytes of the decoded pixels of ``ds`` as its header describes them."""
    rows, cols = int(ds.get("Rows", 0) or 0), int(ds.get("Columns", 0) or 0)
    frames = int(ds.get("NumberOfFrames", 1) or 1)
    samples = int(ds.get("SamplesPerPixel", 1) or 1)
    bits = int(ds.get("BitsAllocated", 8) or 8)
    return rows * cols * frames * samples * max(1, (bits + 7) // 8)


def _refuse_lying_size(file: Path, ds) -> None:
    """Refuse, before decoding, pixel data that cannot hold what the header says."""
    where = f"'{file}'"
    for keyword in ("Rows", "Columns", "NumberOfFrames", "BitsAllocated", "SamplesPerPixel"):
        value = ds.get(keyword, None)
        if value not in (None, "") and (not isinstance(value, (int, float, str))
                                        or int(float(value)) < 0):
            raise DicomError(f"{where}: {keyword} is {value!r}, not a count; the file is corrupt")
    expected = _expected_bytes(ds)
    if expected == 0:
        raise DicomError(f"{where}: Rows or Columns is 0; the file holds no image")
    if expected > MAX_BYTES:
        raise DicomError(
            f"{where}: the header describes {expected / 2 ** 30:.3g} GiB of pixels "
            f"(Rows x Columns x frames x bytes), more than mipcast reads "
            f"({MAX_BYTES / 2 ** 30:g} GiB); the header is corrupt, or split the volume")
    raw = ds.get_item("PixelData")
    length = getattr(raw, "length", None)
    tell = getattr(raw, "value_tell", None)
    size = file.stat().st_size
    if length is not None and length != 0xFFFFFFFF and tell is not None and tell + length > size:
        raise DicomError(f"{where} is truncated: its pixel data should be {length} bytes but the "
                         f"file ends {size - tell} bytes after its start; re-export or re-copy it")
    stored = len(ds.PixelData)
    syntax = getattr(getattr(ds, "file_meta", None), "get", lambda *_: None)("TransferSyntaxUID")
    compressed = syntax is not None and syntax.is_compressed
    if not compressed and stored < expected:
        raise DicomError(
            f"{where}: the header describes {expected} bytes of pixels (Rows x Columns x frames "
            f"x bytes) but the file holds {stored}: truncated file or wrong Rows/Columns/"
            "NumberOfFrames; re-export it")
    if compressed and expected > MAX_COMPRESSION * stored + 2 ** 20:
        raise DicomError(
            f"{where}: the header describes {expected} bytes of pixels but only {stored} "
            f"compressed bytes are stored (more than {MAX_COMPRESSION}:1); the header lies "
            "about Rows/Columns/NumberOfFrames or the file is truncated; re-export it")


def _decode_error(file: Path, ds, error: BaseException) -> DicomError:
    meta = getattr(ds, "file_meta", None)
    syntax = meta.get("TransferSyntaxUID", None) if meta is not None else None
    if syntax is not None and syntax.is_compressed:
        return DicomError(f"cannot decode '{file}': its {syntax.name} pixel data is damaged or "
                          f"does not match Rows/Columns/BitsAllocated (the decoder said: "
                          f"{error}); re-export the file")
    return DicomError(f"cannot decode the pixel data of '{file}': {error}")


def _pixels(file: Path, ds) -> np.ndarray:
    """Decoded pixels of one file as (frames, rows, columns)."""
    problem = _decoder_problem(ds)
    if problem:
        raise DicomError(f"cannot decode '{file}': {problem}")
    if "PixelData" in ds:
        _refuse_lying_size(file, ds)
    try:
        array = ds.pixel_array
    except Exception as error:
        raise _decode_error(file, ds, error) from error
    except BaseException as error:  # Rust decoders (pylibjpeg-rle) panic with a BaseException
        if type(error).__name__ != "PanicException":
            raise
        raise _decode_error(file, ds, error) from None
    frames = int(ds.get("NumberOfFrames", 1) or 1)
    if array.ndim not in (2, 3) or array.size != frames * int(ds.Rows) * int(ds.Columns):
        raise DicomError(f"cannot decode the pixel data of '{file}': decoded shape "
                         f"{array.shape} does not match {frames} frame(s) of "
                         f"{ds.Rows} x {ds.Columns}; the file is corrupt")
    return array.reshape((frames,) + array.shape[-2:])


# ---------------------------------------------------------------------------
# stacking
# ---------------------------------------------------------------------------

def _assemble(frames: List[_Frame], files, pydicom, padding: str = "missing") -> vtkImageData:
    """Check the geometry of ``frames``, sort them along the normal, stack them."""
    first = frames[0]
    headers = {file: ds for file, ds in files}
    size = {f.shape(headers[f.file]) for f in frames}
    if len(size) > 1:
        raise DicomError(f"the images of the series have different sizes {sorted(size)} "
                         "(rows, columns); keep only the slices of one stack")
    rows, cols = size.pop()
    if len(frames) * rows * cols * 8 > MAX_BYTES:
        raise DicomError(
            f"the series describes {len(frames)} slices of {rows} x {cols} pixels, more than "
            f"mipcast reads ({MAX_BYTES / 2 ** 30:g} GiB as float64); the header is corrupt, "
            "or read a part of the series")

    for frame in frames[1:]:
        if np.abs(frame.orientation - first.orientation).max() > ORIENTATION_TOL:
            raise DicomError(
                f"inconsistent orientation: {frame.name} has ImageOrientationPatient "
                f"{_fmt(frame.orientation)} but {first.name} has {_fmt(first.orientation)}; "
                "the series mixes differently oriented images (a scout/localizer or "
                "reformats?): keep only the slices of one stack")
        if np.abs(frame.pixel_spacing - first.pixel_spacing).max() > 1e-4 * first.pixel_spacing.max():
            raise DicomError(
                f"inconsistent PixelSpacing: {frame.name} has {_fmt(frame.pixel_spacing)} but "
                f"{first.name} has {_fmt(first.pixel_spacing)}; keep only the slices of one stack")
    row = first.orientation[:3] / np.linalg.norm(first.orientation[:3])
    col = first.orientation[3:] / np.linalg.norm(first.orientation[3:])
    if abs(float(row @ col)) > ORIENTATION_TOL:
        raise DicomError(
            f"ImageOrientationPatient {_fmt(first.orientation)} of {first.name} is not made of "
            "two perpendicular unit vectors; the files are corrupt")
    normal = np.cross(row, col)
    normal /= np.linalg.norm(normal)

    positions = np.array([f.position for f in frames])
    along = positions @ normal
    order = np.argsort(along, kind="stable")
    frames = [frames[i] for i in order]
    positions, along = positions[order], along[order]
    pixel = float(first.pixel_spacing.min())

    if len(frames) == 1:
        ds = headers[first.file]
        step = None
        for keyword in ("SpacingBetweenSlices", "SliceThickness"):
            value = ds.get(keyword, None)
            if value not in (None, "") and float(value) > 0:
                step = float(value)
                break
        step = step or 1.0  # one slice: the step has no effect on any point
        origin = positions[0]
        index = depths = None
    else:
        step, origin, tilt, index, depths = _check_steps(frames, positions, along, normal, pixel)

    ds0 = headers[first.file]
    values = _stack(frames, headers, rows, cols, padding, index)
    if len(frames) > 1 and tilt is not None:
        # slice k lies k x step x tilt sideways of the grid: sample it where the grid's points are
        per_slice = step * np.array([float(tilt @ row) / float(first.pixel_spacing[1]),
                                     float(tilt @ col) / float(first.pixel_spacing[0])])
        reach = depths[-1] if depths is not None else values.GetNumberOfTuples() // (rows * cols) - 1
        per_slice[np.abs(per_slice) * reach < TILT_TOL_PIXELS] = 0.0  # the headers' rounding
        values = _untilted(values, rows, cols, per_slice, depths)
    if depths is not None:
        values = _resampled(values, rows, cols, depths)
    depth = values.GetNumberOfTuples() // (rows * cols)  # grid slices, missing ones included
    image = vtkImageData()
    image.SetDimensions(cols, rows, depth)
    # PixelSpacing = (between rows, between columns) = (along j, along i)
    image.SetSpacing(float(first.pixel_spacing[1]), float(first.pixel_spacing[0]), step)
    image.SetOrigin(*(float(v) for v in origin))
    image.SetDirectionMatrix(*np.column_stack([row, col, normal]).ravel())
    values.SetName(SCALARS_NAME)
    image.GetPointData().SetScalars(values)
    units = vtkStringArray()
    units.SetName(UNITS_NAME)
    units.InsertNextValue(_units(ds0, first.rescale_type))
    image.GetFieldData().AddArray(units)
    _add_windows(image, _series_windows(frames, headers))
    return image


def _check_steps(frames, positions, along, normal, pixel):
    """Fit a regular grid to the slice positions; return (step, origin, tilt, index, depths).

    Duplicates, scattered origins, gaps that are no whole number of steps
    and slices more than ``POSITION_TOL`` x step off the least-squares grid
    are refused, naming the slices.  Within the tolerance, the least-squares
    step and origin are used and one :class:`DicomGeometryWarning` gives the
    largest misplacement.  ``tilt``: None, or the gantry tilt's sideways
    drift of the slices per mm along the normal (a vector perpendicular to
    it), for :func:`_untilted`; the origin is then the first grid slice's
    corner.  ``index``: each slice's place on the grid (:func:`_grid_index`;
    missing slices leave places empty).  ``depths``: None, or, for a series
    whose spacing changes in zones (:func:`_zones`), each slice's distance
    from the first in grid steps (the finest zone's step), to resample it
    (:func:`_resampled`; ``index`` is then None).
    """
    steps = np.diff(along)
    _refuse_duplicates(frames, along, steps)
    lateral, scatter, tilt = _check_lateral(frames, positions, along, normal, pixel)
    zones = _zones(steps)
    if zones is not None:
        finest = min(float(np.median(steps[a:b])) for a, b in zones)
        described = ", then ".join(f"{b - a} steps of {float(np.median(steps[a:b])):.4g} mm" for a, b in zones)
        count = int(np.ceil((along[-1] - along[0]) / finest - 1e-6)) + 1  # the ends on the grid, no step coarser
        step = float(along[-1] - along[0]) / (count - 1)
        warnings.warn(
            f"the slice spacing changes along the series ({described}, from {frames[0].name}): resampled "
            f"linearly along the slice normal onto a regular grid of {step:.4g} mm ({count} slices; float32), "
            "so values between the coarser slices are interpolated", DicomGeometryWarning, stacklevel=caller_level())
        origin = positions[0] + (lateral[0] if tilt is not None else lateral.mean(axis=0))
        return step, origin, tilt, None, (along - along[0]) / step
    index = _grid_index(frames, along, steps)
    k = index.astype(float)
    step = float((along[-1] - along[0]) / index[-1])
    intercept = float(along[0])
    if np.abs(along - (intercept + step * k)).max() > 1e-6 * step:  # not exactly even
        step, intercept = (float(v) for v in np.polyfit(k, along, 1))
    residual = along - (intercept + step * k)
    worst = int(np.argmax(np.abs(residual)))
    if abs(residual[worst]) > POSITION_TOL * step:
        raise DicomError(
            f"the slice positions are not evenly spaced: {frames[worst].name} lies "
            f"{abs(residual[worst]):.3g} mm off the best regular grid (step {step:.4g} mm; "
            f"steps range from {steps.min():.4g} to {steps.max():.4g} mm; limit "
            f"{POSITION_TOL:g} x the step). The folder probably mixes stacks with different "
            "spacing; keep the slices of one stack (or resample the series to a uniform step "
            "first)")
    misplacement = np.sqrt(residual ** 2 + scatter ** 2)
    worst = int(np.argmax(misplacement))
    if misplacement[worst] > max(WARN_TOL * step, 1e-4):
        warnings.warn(
            f"the slice positions deviate from a regular grid (steps {steps.min():.4g} to "
            f"{steps.max():.4g} mm, rounded positions in the headers?): using the least-squares "
            f"step {step:.6g} mm; the largest misplacement is {misplacement[worst]:.3g} mm "
            f"({100 * misplacement[worst] / step:.2g} % of the step) at {frames[worst].name}",
            DicomGeometryWarning, stacklevel=caller_level())
    depth = intercept - along[0]  # the grid's first slice along the normal, from the first frame
    if tilt is None:
        return step, positions[0] + depth * normal + lateral.mean(axis=0), None, index, None
    return step, positions[0] + depth * normal + lateral[0] + depth * tilt, tilt, index, None


def _zones(steps: np.ndarray) -> Optional[List[Tuple[int, int]]]:
    """The runs ``(first, end)`` of near-equal steps (within ``POSITION_TOL`` of the run's median) when the
    spacing changes in zones: two runs or more, each of two steps or more; else None (one spacing, with
    perhaps single gaps: :func:`_grid_index`)."""
    runs = [[0, 1]]
    for i in range(1, len(steps)):
        start = runs[-1][0]
        usual = float(np.median(steps[start:i]))
        if abs(steps[i] - usual) <= POSITION_TOL * usual:
            runs[-1][1] = i + 1
        else:
            runs.append([i, i + 1])
    if len(runs) < 2 or any(end - start < 2 for start, end in runs):
        return None
    return [(start, end) for start, end in runs]


def _refuse_duplicates(frames, along, steps) -> None:
    nonzero = steps[steps > 1e-6]
    median = float(np.median(nonzero)) if nonzero.size else 0.0
    duplicates = np.flatnonzero(steps <= max(1e-4, DUPLICATE_FACTOR * median))
    if duplicates.size:
        pairs = "; ".join(f"{frames[d].name} and {frames[d + 1].name} at {along[d]:.3f} mm"
                          for d in duplicates[:3])
        raise DicomError(
            f"{duplicates.size} duplicate slice position(s) along the slice normal ({pairs}"
            f"{'; ...' if duplicates.size > 3 else ''}): the series holds several images per "
            "position (repeated files, several time points, echoes or acquisitions?); keep "
            "one image per position (e.g. one acquisition/echo per folder)")


def _grid_index(frames, along, steps) -> np.ndarray:
    """Each slice's place on the regular grid: 0, 1, 2, ... with the places of missing slices left out.

    A step of m times the usual one (m a whole number >= 2, within ``POSITION_TOL``) is m - 1 missing
    slices: their places hold missing data (NaN), with one :class:`DicomGeometryWarning` naming the
    gaps.  A gap that is no whole number of steps (stacks of different spacing), two large steps in
    a row (a zone of coarser slices), or more missing slices than present ones, is refused.
    """
    # the usual step: the median of the steps near the smallest (gaps may be most of the steps)
    median = float(np.median(steps[steps <= GAP_FACTOR * steps.min()]))
    multiples = steps / median
    gaps = np.flatnonzero(steps > GAP_FACTOR * median)
    if not gaps.size:
        return np.arange(len(along))
    whole = np.rint(multiples)
    counts = (whole[gaps] - 1).astype(int)
    where = "; ".join(
        f"between {frames[g].name} ({along[g]:.3f} mm) and {frames[g + 1].name} ({along[g + 1]:.3f} mm): "
        f"{multiples[g]:.3g} steps" for g in gaps[:3]) + ("; ..." if gaps.size > 3 else "")
    uneven = np.abs(multiples[gaps] - whole[gaps]) > POSITION_TOL
    if (np.diff(gaps) == 1).any():  # large steps in a row, but no clean zones (_zones): spacings mixed
        first = int(gaps[np.flatnonzero(np.diff(gaps) == 1)[0]])
        raise DicomError(
            f"the slice spacing changes irregularly along the series: from {frames[first].name} "
            f"({along[first]:.3f} mm) the steps are {steps[first]:.4g}, {steps[first + 1]:.4g} ... mm against "
            f"{median:.4g} mm elsewhere, in no zones of one spacing each; keep the slices of one stack")
    if uneven.any() or counts.sum() > len(along):
        reason = ("no whole number of steps: the folder mixes stacks with different spacing"
                  if uneven.any() else f"{counts.sum()} missing, more than the {len(along)} present")
        raise DicomError(
            f"missing slice(s): {gaps.size} gap(s) larger than {GAP_FACTOR} x the usual step of "
            f"{median:.4g} mm ({where}), {reason}; copy the whole series into the folder (or keep the "
            "slices of one stack)")
    warnings.warn(
        f"{counts.sum()} missing slice(s) in {gaps.size} gap(s) of the usual step of {median:.4g} mm "
        f"({where}): their places hold missing data (NaN; the volume becomes float32), drawn as "
        "background; copy the whole series into the folder to fill them",
        DicomGeometryWarning, stacklevel=caller_level())
    return np.concatenate([[0], np.cumsum(np.where(steps > GAP_FACTOR * median, whole, 1.0))]).astype(int)


def _check_lateral(frames, positions, along, normal, pixel):
    """Find gantry tilt, refuse scattered origins; return (lateral offsets, their scatter, tilt).

    A steady sideways drift of the slice origins (up to :data:`MAX_TILT_DEG`) is gantry tilt: ``tilt``
    is the drift per mm along the normal, the offsets are those of the fitted line (its first point)
    and the scatter is about the line.  Otherwise ``tilt`` is None and the scatter is about the mean.
    """
    offsets = positions - positions[0]
    lateral = offsets - np.outer(offsets @ normal, normal)
    depth = along - along[0]
    design = np.column_stack([np.ones_like(depth), depth])
    (base, slope), *_ = np.linalg.lstsq(design, lateral, rcond=None)
    fitted = base + np.outer(depth, slope)
    noise = float(np.linalg.norm(lateral - fitted, axis=1).max())
    drift = float(np.linalg.norm(slope) * depth[-1])
    angle = math.degrees(math.atan(float(np.linalg.norm(slope))))
    tilt = None
    if drift > max(TILT_TOL_PIXELS * pixel + 3 * noise, 1e-3):
        if angle > MAX_TILT_DEG:
            raise DicomError(
                f"the slice origins drift sideways to the slice normal by {drift:.3f} mm from "
                f"{frames[0].name} to {frames[-1].name} ({angle:.1f} deg, more than a gantry tilts, "
                f"{MAX_TILT_DEG:g} deg): the folder mixes stacks; keep the slices of one stack")
        tilt = slope
        warnings.warn(
            f"gantry tilt of about {angle:.2f} deg (the slice origins drift {drift:.3f} mm sideways from "
            f"{frames[0].name} to {frames[-1].name}): the slices are shifted onto an untilted grid by up to "
            f"{drift / pixel:.3g} pixels (linear interpolation along the shift); the voxels no slice covers "
            "are missing (NaN)", DicomGeometryWarning, stacklevel=caller_level())
        lateral = fitted  # the grid follows the line; what is off it is scatter
        scatter = np.linalg.norm(offsets - np.outer(offsets @ normal, normal) - fitted, axis=1)
    else:
        scatter = np.linalg.norm(lateral - lateral.mean(axis=0), axis=1)
    worst = int(np.argmax(scatter))
    if scatter[worst] > LATERAL_TOL_PIXELS * pixel:
        raise DicomError(
            f"the slice origins are scattered sideways to the slice normal: {frames[worst].name} "
            f"is {scatter[worst]:.3g} mm off the others (limit {LATERAL_TOL_PIXELS:g} pixel = "
            f"{LATERAL_TOL_PIXELS * pixel:.3g} mm); the folder mixes stacks: keep the slices "
            "of one stack")
    return lateral, scatter, tilt


def _untilted(values: vtkDataArray, rows: int, cols: int, per_slice: np.ndarray,
              depths: Optional[np.ndarray] = None) -> vtkDataArray:
    """The stacked slices (nz, rows, cols) with slice k sampled ``depths[k] x per_slice`` pixels (columns, rows)
    back (``depths`` default k): a new float32 array, linear between pixels, NaN where slice k has no pixel."""
    stacked = vtk_to_numpy(values).reshape(-1, rows, cols).astype(np.float64)
    out = np.empty(stacked.shape, dtype=np.float32)
    for k, plane in enumerate(stacked):
        depth = k if depths is None else float(depths[k])
        plane = _shifted(plane, depth * per_slice[1], axis=0)  # along the rows (the column direction)
        out[k] = _shifted(plane, depth * per_slice[0], axis=1)
    return numpy_to_vtk(out.ravel(), deep=True)


def _resampled(values: vtkDataArray, rows: int, cols: int, depths: np.ndarray) -> vtkDataArray:
    """The stacked slices, slice k at ``depths[k]`` grid steps from the first (the last at a whole number),
    resampled at whole steps 0, 1, ...: linear between the two nearest slices (a new float32 array)."""
    stacked = vtk_to_numpy(values).reshape(-1, rows, cols)
    grid = np.arange(int(np.floor(depths[-1] + 1e-6)) + 1, dtype=float)
    lower = np.clip(np.searchsorted(depths, grid, side="right") - 1, 0, len(depths) - 2)
    weight = np.clip((grid - depths[lower]) / (depths[lower + 1] - depths[lower]), 0.0, 1.0)
    out = np.empty((len(grid), rows, cols), dtype=np.float32)
    for k, (i, w) in enumerate(zip(lower, weight)):
        if w <= 1e-9:
            out[k] = stacked[i]
        elif w >= 1.0 - 1e-9:
            out[k] = stacked[i + 1]
        else:
            out[k] = stacked[i] * (1.0 - w) + stacked[i + 1] * w
    return numpy_to_vtk(out.ravel(), deep=True)


def _shifted(plane: np.ndarray, shift: float, axis: int) -> np.ndarray:
    """``plane`` sampled at index - ``shift`` along ``axis``: linear, NaN beyond its first and last pixel."""
    if abs(shift) < 1e-9:
        return plane
    n = plane.shape[axis]
    where = np.arange(n) - shift
    inside = np.clip(where, 0.0, n - 1.0)
    low = np.minimum(np.floor(inside).astype(int), max(n - 2, 0))
    high = np.minimum(low + 1, n - 1)
    weight = inside - low
    a, b = np.take(plane, low, axis=axis), np.take(plane, high, axis=axis)
    shape = [1, 1]
    shape[axis] = n
    weight = weight.reshape(shape)
    result = a * (1.0 - weight) + b * weight
    outside = ((where < -1e-3) | (where > n - 1 + 1e-3)).reshape(shape)
    return np.where(outside, np.nan, result)


def _stack(frames: List[_Frame], headers, rows: int, cols: int, padding: str = "missing",
           index: Optional[np.ndarray] = None) -> vtkDataArray:
    """Decode, rescale and stack the frames into a new VTK array (nz, ny, nx); padded pixels NaN
    (:func:`_padded`); frame k at grid slice ``index[k]`` (default k), the slices no frame fills NaN."""
    decoded: Dict[Path, np.ndarray] = {}
    raw = []
    for frame in frames:
        if frame.file not in decoded:
            decoded[frame.file] = _pixels(frame.file, headers[frame.file])
        raw.append(frame.pixels(decoded[frame.file]))
    slopes = np.array([f.slope for f in frames])
    intercepts = np.array([f.intercept for f in frames])
    padded = _padded(frames, headers, raw, padding)
    integral = (all(a.dtype.kind in "iub" for a in raw)
                and all(float(v).is_integer() for v in np.concatenate([slopes, intercepts])))
    slots = np.arange(len(frames)) if index is None else np.asarray(index)
    depth = int(slots[-1]) + 1
    if padded is not None or depth > len(frames):
        integral = False  # NaN needs floats
    if integral:
        lows, highs = [], []
        for array, slope, intercept in zip(raw, slopes, intercepts):
            ends = np.array([int(array.min()), int(array.max())], dtype=float) * slope + intercept
            lows.append(ends.min())
            highs.append(ends.max())
        dtype = integer_dtype(min(lows), max(highs))
    else:
        dtype = np.dtype(np.float32)
    array = vtkDataArray.CreateDataArray(get_vtk_array_type(dtype))
    array.SetNumberOfComponents(1)
    array.SetNumberOfTuples(depth * rows * cols)
    out = vtk_to_numpy(array).reshape(depth, rows, cols)
    if depth > len(frames):
        out[:] = np.nan  # missing slices
    for k, (slot, pixels, slope, intercept) in enumerate(zip(slots, raw, slopes, intercepts)):
        if slope == 1 and intercept == 0:
            out[slot] = pixels
        elif integral and dtype.kind in "iu":
            out[slot] = pixels.astype(np.int64) * int(slope) + int(intercept)
        else:
            out[slot] = pixels.astype(np.float64) * slope + intercept
        if padded is not None:
            out[slot][padded[k]] = np.nan
    return array


def _padding_range(ds) -> Optional[Tuple[float, float]]:
    """(lowest, highest) stored value that is padding (PixelPaddingValue up to PixelPaddingRangeLimit), or None."""
    try:
        value = ds.get("PixelPaddingValue", None)
        if value is None or value == "":
            return None
        limit = ds.get("PixelPaddingRangeLimit", None)
        ends = [float(value), float(value if limit in (None, "") else limit)]
    except (TypeError, ValueError):  # an unreadable tag: nothing is padding
        return None
    return min(ends), max(ends)


def _lossy(ds) -> bool:
    flag = str(ds.get("LossyImageCompression", "") or "").strip()
    if flag:
        return flag == "01"
    meta = getattr(ds, "file_meta", None)
    return str(getattr(meta, "TransferSyntaxUID", "") or "") in LOSSY_SYNTAXES


def _padded(frames: List[_Frame], headers, raw, padding: str) -> Optional[List[np.ndarray]]:
    """Per frame, the pixels holding the padding value (stored values), or None when none are read as missing.

    One :class:`DicomPaddingWarning` says how many were read as missing, or why they were kept
    (lossy compression).
    """
    ranges = [_padding_range(headers[f.file]) for f in frames]
    if padding == "keep" or all(r is None for r in ranges):
        return None
    masks = [np.zeros(a.shape, dtype=bool) if r is None else (a >= r[0]) & (a <= r[1])
             for a, r in zip(raw, ranges)]
    count = sum(int(m.sum()) for m in masks)
    if count == 0:
        return None
    value = next(r for r in ranges if r is not None)
    shown = f"{value[0]:g}" if value[0] == value[1] else f"{value[0]:g}..{value[1]:g}"
    total = sum(m.size for m in masks)
    if any(_lossy(headers[f.file]) for f in frames):
        warnings.warn(
            f"the series is lossy compressed: its PixelPaddingValue {shown} (stored) no longer marks the "
            f"pixels outside the scanned field exactly ({count} of {total} pixels hold it, their neighbours "
            "were moved off it), so the padding is kept as values; a window above it hides it",
            DicomPaddingWarning, stacklevel=caller_level())
        return None
    warnings.warn(
        f"{count} of {total} pixels ({100.0 * count / total:.1f} %) hold the PixelPaddingValue {shown} "
        "(stored; pixels outside the scanned field): read as missing data (NaN, float32) so that no "
        "projection, average or default window counts them; read_dicom(..., padding='keep'), "
        "read_volume(..., padding='keep') or `mipcast render/view --padding keep` keeps them as values",
        DicomPaddingWarning, stacklevel=caller_level())
    return masks


def integer_dtype(low: float, high: float) -> np.dtype:
    """The smallest of int16, int32, uint32 holding [low, high], else float64.

    Examples
    --------
    >>> integer_dtype(-1024, 3071).name, integer_dtype(0, 65535).name
    ('int16', 'int32')
    """
    for candidate in (np.int16, np.int32, np.uint32):
        info = np.iinfo(candidate)
        if info.min <= low and high <= info.max:
            return np.dtype(candidate)
    return np.dtype(np.float64)


def _units(ds, rescale_type: str) -> str:
    modality = str(ds.get("Modality", "") or "").upper()
    if modality == "RTDOSE":
        units = str(ds.get("DoseUnits", "") or "")
        return {"GY": "Gy", "RELATIVE": "relative"}.get(units.upper(), units)
    if rescale_type and rescale_type.upper() != "US":  # US = unspecified
        return rescale_type
    if modality == "CT":
        return "HU"
    if modality == "PT":
        return str(ds.get("Units", "") or "")
    return ""


def _frame_windows(frame: _Frame, ds) -> tuple:
    """One frame's VOI windows, ``((low, high, explanation), ...)``, in the rescaled values' units.

    From the frame's FrameVOILUTSequence (an enhanced multi-frame file: per frame, else shared), else the
    dataset's WindowCenter / WindowWidth (each may hold several windows, named by
    WindowCenterWidthExplanation).  DICOM PS3.3 C.11.2.1.2: VOILUTFunction LINEAR (the default) maps
    ``c - 0.5 - (w - 1) / 2`` to black and ``c - 0.5 + (w - 1) / 2`` to white; LINEAR_EXACT ``c -+ w / 2``;
    SIGMOID, which has no ends, gets LINEAR_EXACT's (its 12 % and 88 % points).  Windows that are not
    numbers or not wider than 0 are left out.
    """
    source = ds
    if frame.tile is None:
        per_frame = ds.get("PerFrameFunctionalGroupsSequence", None)
        own = per_frame[frame.index] if per_frame is not None and frame.index is not None \
            and frame.index < len(per_frame) else None
        for group in (own, _first_item(ds, "SharedFunctionalGroupsSequence")):
            item = _first_item(group, "FrameVOILUTSequence")
            if item is not None and item.get("WindowCenter", None) is not None:
                source = item
                break
    try:
        centres = _as_list(source.get("WindowCenter", None))
        widths = _as_list(source.get("WindowWidth", None))
        names = _as_list(source.get("WindowCenterWidthExplanation", None))
        function = str(source.get("VOILUTFunction", None) or ds.get("VOILUTFunction", None) or "LINEAR")
    except (TypeError, ValueError):  # a damaged value: no window, the picture does not depend on it
        return ()
    windows = []
    for k, (centre, width) in enumerate(zip(centres, widths)):
        try:
            centre, width = float(centre), float(width)
        except (TypeError, ValueError):
            continue
        if not (math.isfinite(centre) and math.isfinite(width) and width > 0):
            continue
        if function.strip().upper() == "LINEAR" and width >= 1:
            low, high = centre - 0.5 - (width - 1) / 2, centre - 0.5 + (width - 1) / 2
        else:
            low, high = centre - width / 2, centre + width / 2
        if high > low:
            windows.append((low, high, str(names[k]).strip() if k < len(names) else ""))
    return tuple(windows)


def _as_list(value) -> list:
    """A DICOM value of multiplicity 1-n as a list (``[]`` when absent)."""
    if value is None or value == "":
        return []
    # pydicom's MultiValue is a Sequence; a one-value element is a number or a string
    return list(value) if isinstance(value, abc.Sequence) and not isinstance(value, (str, bytes)) else [value]


def _series_windows(frames: List[_Frame], headers) -> tuple:
    """The series' windows: those most frames share (a CT's, every slice the same), or, where no set of
    windows is shared by half the frames (an MR scanner's window chosen per slice), one window from the
    median centre and median width of each frame's first, named "median of the slices' windows"."""
    per_frame = [_frame_windows(frame, headers[frame.file]) for frame in frames]
    shared = Counter(windows for windows in per_frame if windows)
    if not shared:
        return ()
    windows, count = shared.most_common(1)[0]
    if 2 * count >= len(frames):
        return windows
    firsts = np.array([windows[0][:2] for windows in per_frame if windows])
    centre = float(np.median(firsts.mean(axis=1)))
    width = float(np.median(firsts[:, 1] - firsts[:, 0]))
    return ((centre - width / 2, centre + width / 2, "median of the slices' windows"),)


def _add_windows(image: vtkImageData, windows: tuple) -> None:
    """``windows`` as the field data :data:`WINDOWS_NAME` and :data:`WINDOW_NAMES_NAME` (nothing if none)."""
    if not windows:
        return
    ends = numpy_to_vtk(np.array([w[:2] for w in windows], dtype=np.float64), deep=True)
    ends.SetName(WINDOWS_NAME)
    names = vtkStringArray()
    names.SetName(WINDOW_NAMES_NAME)
    for window in windows:
        names.InsertNextValue(window[2])
    image.GetFieldData().AddArray(ends)
    image.GetFieldData().AddArray(names)


def _fmt(values) -> str:
    return "[" + ", ".join(f"{float(v):.6g}" for v in values) + "]"

"""The default grey window: what a viewer shows when the user gives no range.

A MIP keeps the brightest value along each ray, so the data range is a poor
window: the noisy background's maxima come out as a grey box and one hot
voxel (metal, a dental filling) darkens everything else.  The rule here,
also stated in docs/usage.md ("The default window"):

- **CT** (Hounsfield units): the ``"ct-mip"`` preset, 150 to 1800 HU (the
  high end lowered to the data maximum if that is below 1800; a CT whose
  maximum is not above 150 HU gets the histogram rule below).  Soft
  tissue, blood and water (< 150 HU) are black; contrast-filled vessels
  (~150-500 HU) and bone (~300-2000 HU) show.  The data count as HU when
  the image's field data ``"units"`` says ``"HU"`` (the DICOM reader records
  it for Modality CT or RescaleType HU), when the scalars are named ``"HU"``
  (the bundled head CT), or when the scalars are signed integers whose 1st
  percentile lies within -1100..-900 (air at -1000) and whose maximum is
  above 300.
- **Anything else**: percentiles of the histogram.  ``low`` = median + 3
  robust standard deviations (1.4826 x the median absolute deviation), the
  brightest the background noise reaches in a projection, but at most the
  99.5th percentile of the voxels and of the trilinear interpolant at the
  cell centres (so at least 0.5 % of the voxels, and of what rays between
  them meet, are above it: white noise averages out between voxels); ``high``
  = the 99.5th percentile of the voxels above ``low`` (a few of the
  brightest voxels saturate).  Where that gives no range, the data range.

That is the rule for a MIP (``projection="mip"``, the method table's
``Method.projection``).  The other projections keep other values, so they
get other windows:

- **MinIP** (``"minip"``) keeps the darkest value: the rule mirrored.  CT:
  the ``"ct-minip"`` preset, -1000 to -400 HU (air and airways dark, lung
  parenchyma grey, soft tissue white).  Anything else: ``high`` = median -
  3 robust standard deviations, the darkest the bright surround (tissue)
  reaches in a projection, but at least the 0.5th percentile (of the voxels
  and of the interpolant at the cell centres); ``low`` = the
  0.5th percentile of the voxels below ``high`` (the darkest structures,
  air, at the bottom).
- **Average** (``"average"``) keeps the mean, which lies in a much
  narrower range than the voxels: the 1st to 99th percentiles of the
  volume's average projections along its three index axes (what an
  average projection shows, for any view, approximately), CT included: a
  whole-volume average mixes the air around the body into every ray, so a
  soft-tissue window (``"ct-soft"``, -160 to 240 HU, the right one for a
  thin slab inside the body) would draw it nearly black.

``"full"`` is the data range (the default before this rule), ``"auto"`` the
rule, a preset name (:data:`PRESETS`) its window, ``"dicom"`` the first of the
windows a DICOM series carries (its WindowCenter / WindowWidth, recorded by
:func:`mipcast.io.dicom.read_dicom`; ``"dicom:2"`` or ``"dicom:BONE"`` another,
:func:`dicom_windows`), and ``(low, high)`` itself, whatever the projection.
The DICOM windows are not the default: a scanner sets them for reading
slices (a CT's soft-tissue window, 40 / 400, saturates a MIP through a whole
head wherever bone or contrast lies on the ray), but a CT angiography
series often carries the window its MIPs are read with.

Missing voxels (NaN, +-Inf) are no part of any window: the rules and
``"full"`` see the finite values only (callers pass
:func:`mipcast.mappers.input_preparer.window_image`, which leaves them NaN
whatever a projection fills them with).

Examples
--------
>>> from mipcast.data_fixtures import make_fixture
>>> low, high = default_window(make_fixture("vessels", size=32))
>>> 0.15 < low < 0.3 < 0.8 < high <= 1.0
True
>>> resolve_window(make_fixture("spheres", size=16), "full")
(0.0, 1.0)
>>> low, high = default_window(make_fixture("airways", size=32), "minip")
>>> 0.0 <= low < 0.2 < 0.6 < high < 0.8
True
"""
from __future__ import annotations

from typing import List, Optional, Sequence, Tuple, Union

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

#: Named windows (low, high) in data units; CT ones in HU.  ``ct-mip`` is the
#: default for CT (the window docs/images/depth_figure.png has always used
#: for the head CT: contrast and bone, the skull not saturated);
#: ``ct-bone`` is the usual bone window (width 2000, level 500);
#: ``ct-angio`` a CT angiography window (width 700, level 200).
#: ``ct-minip`` the default for a CT MinIP (airways: air to lung), ``ct-soft``
#: for a CT average (soft tissue, width 400, level 40).
PRESETS = {"ct-mip": (150.0, 1800.0), "ct-bone": (-500.0, 1500.0), "ct-angio": (-150.0, 550.0),
           "ct-minip": (-1000.0, -400.0), "ct-soft": (-160.0, 240.0)}
#: The projections the default window has a rule for (``Method.projection``).
PROJECTIONS = ("mip", "minip", "average")
#: The words :func:`resolve_window` takes besides presets and (low, high) (``"dicom"`` also as
#: ``"dicom:K"`` or ``"dicom:NAME"``).
KEYWORDS = ("auto", "full", "dicom")
#: At most this many voxels enter the percentiles (an even stride over the rest).
SAMPLE_LIMIT = 2_000_000

WindowSpec = Union[None, str, Sequence[float]]


def data_range(image) -> Tuple[float, float]:
    """(min, max) of the active point scalars' finite values (NaN and +-Inf are missing data)."""
    low, high = image.GetPointData().GetScalars().GetFiniteRange(0)
    return float(low), float(high)


def constant_window(value: float) -> Tuple[float, float]:
    """The window of a constant volume (or ``"full"`` of one): one unit wide, the value in its middle.

    The volume then draws a uniform mid grey, seen against the background; a window starting at the value
    (the data range widened upwards) drew it black, the background's colour.

    Examples
    --------
    >>> constant_window(7.0)
    (6.5, 7.5)
    """
    return (float(value) - 0.5, float(value) + 0.5)


def units(image) -> str:
    """The image's units: field data ``"units"`` if present, else ``"HU"`` for scalars named so, else ``""``.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> units(make_fixture("spheres", size=8))
    ''
    """
    array = image.GetFieldData().GetAbstractArray("units")
    if array is not None and array.GetNumberOfValues() > 0:
        return str(array.GetVariantValue(0).ToString())
    name = image.GetPointData().GetScalars().GetName() or ""
    return "HU" if name.upper() == "HU" else ""


def dicom_windows(image) -> List[Tuple[str, Tuple[float, float]]]:
    """The grey windows a DICOM series carries: ``[(name, (low, high)), ...]``, the scanner's first first.

    Read from the field data :func:`mipcast.io.dicom.read_dicom` records (its WindowCenter / WindowWidth as
    DICOM's VOILUTFunction maps them; ``name`` its WindowCenterWidthExplanation, ``""`` where it has none).
    ``[]`` for a volume that carries none.

    Examples
    --------
    >>> import os
    >>> from pydicom.data import get_testdata_file
    >>> from mipcast.io.dicom import read_dicom
    >>> dicom_windows(read_dicom(os.path.dirname(get_testdata_file("dicomdirtests/98892001/CT5N/2062"))))
    [('', (-160.0, 239.0))]
    """
    ends = image.GetFieldData().GetArray("dicom_windows")
    if ends is None or ends.GetNumberOfComponents() != 2:
        return []
    names = image.GetFieldData().GetAbstractArray("dicom_window_names")
    count = names.GetNumberOfValues() if names is not None else 0
    return [(str(names.GetValue(k)) if k < count else "", (float(ends.GetComponent(k, 0)), float(ends.GetComponent(k, 1))))
            for k in range(ends.GetNumberOfTuples())]


def _dicom_window(image, word: str) -> Tuple[float, float]:
    """``"dicom"`` (the first), ``"dicom:K"`` (1-based) or ``"dicom:NAME"`` (case-insensitive): that window."""
    windows = dicom_windows(image)
    if not windows:
        raise ValueError(f"window {word!r} is a DICOM series' own window (WindowCenter / WindowWidth, recorded by "
                         "mipcast.io.read_dicom), and this volume carries none: give LOW HIGH, 'auto', 'full' or "
                         f"a preset ({', '.join(sorted(PRESETS))})")
    choice = word.partition(":")[2].strip()
    if not choice:
        return windows[0][1]
    for index, (name, window) in enumerate(windows, 1):
        if choice == str(index) or (name and choice.lower() == name.lower()):
            return window
    raise ValueError(f"window {word!r}: the series' windows are {describe_dicom_windows(windows)}")


def describe_dicom_windows(windows: Sequence[Tuple[str, Tuple[float, float]]]) -> str:
    """``dicom_windows`` in words, each as the word that picks it: ``dicom (ANGIO: -150 to 550), dicom:2 (...)``."""
    return ", ".join(f"dicom{'' if k == 1 else f':{k}'} ({name + ': ' if name else ''}{low:.6g} to {high:.6g})"
                     for k, (name, (low, high)) in enumerate(windows, 1))


def window_choices(image, projection: str = "mip") -> List[Tuple[str, Tuple[float, float]]]:
    """The windows a viewer offers in turn (``mipcast view``'s ``w`` key): ``[(word, (low, high)), ...]``.

    The projection's default rule (``"auto"``), the windows a DICOM series carries (``"dicom"``,
    ``"dicom:2"``, ... with their names), the CT presets for Hounsfield units, and the data range
    (``"full"``); a window equal to an earlier one, or beside the data (a MinIP preset above a CT's
    air-free data), is left out.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> [word for word, _ in window_choices(make_fixture("spheres", size=16))]
    ['auto']
    """
    choices = [("auto", default_window(image, projection))]
    choices += [(f"dicom{'' if k == 1 else f':{k}'}" + (f" ({name})" if name else ""), window)
                for k, (name, window) in enumerate(dicom_windows(image), 1)]
    if looks_like_ct(image):
        choices += [(name, PRESETS[name]) for name in ("ct-mip", "ct-angio", "ct-bone", "ct-soft", "ct-minip")]
    full = resolve_window(image, "full")
    choices.append(("full", full))
    unique = []
    for word, window in choices:
        if all(window != seen for _, seen in unique) and window[1] > full[0] and window[0] < full[1]:
            unique.append((word, window))
    return unique


def looks_like_ct(image, values: Optional[np.ndarray] = None) -> bool:
    """Whether the scalars are Hounsfield units (see the module docstring for the rule).

    Examples
    --------
    >>> import numpy as np
    >>> from mipcast.data_fixtures.synthetic import image_from_array
    >>> ct = np.full((8, 8, 8), -1000, np.int16); ct[2:6, 2:6, 2:6] = 800
    >>> looks_like_ct(image_from_array(ct)), looks_like_ct(image_from_array(ct.astype(np.float32)))
    (True, False)
    """
    if units(image).upper() == "HU":
        return True
    values = _sample(image) if values is None else values
    if not np.issubdtype(values.dtype, np.signedinteger) or values.size == 0:
        return False
    return -1100.0 <= float(np.percentile(values, 1)) <= -900.0 and float(values.max()) > 300.0


def default_window(image, projection: str = "mip") -> Tuple[float, float]:
    """The window a viewer would pick for ``image`` drawn as ``projection`` (module docstring: the rule).

    Parameters
    ----------
    image : vtkImageData
        The volume.
    projection : {"mip", "minip", "average"}, default: "mip"
        What the method keeps along a ray (the method table's ``Method.projection``).

    Returns
    -------
    tuple of float
        (low, high) with high > low in data units; for constant data
        :func:`constant_window` (the value mid-window: a uniform mid grey).
    """
    return window_and_reason(image, projection)[0]


def window_and_reason(image, projection: str = "mip") -> Tuple[Tuple[float, float], str]:
    """:func:`default_window` and a few words saying which rule chose it (for messages).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> window_and_reason(make_fixture("spheres", size=16))[1]
    'histogram percentiles'
    """
    if projection not in PROJECTIONS:
        raise ValueError(f"projection must be one of {', '.join(PROJECTIONS)}; got {projection!r}")
    values = _sample(image)
    full = data_range(image)
    if projection != "mip":
        return _other_window(image, values, full, projection)
    if looks_like_ct(image, values):
        low, high = PRESETS["ct-mip"]
        high = min(high, full[1])
        if high > low:
            return (low, high), "CT preset ct-mip (HU)"
    if values.size:
        values = values.astype(np.float64, copy=False)
        median = float(np.median(values))
        spread = 1.4826 * float(np.median(np.abs(values - median)))
        low = float(np.nanmin([median + 3.0 * spread, np.percentile(values, 99.5), _cell_percentile(image, 99.5)]))
        above = values[values > low]
        if above.size:
            high = float(np.percentile(above, 99.5))
            if not high > low:
                high = float(above.max())
            if high > low:
                return (low, high), "histogram percentiles"
    if full[1] > full[0]:
        return full, "data range"
    return constant_window(full[0]), "constant data"


def _other_window(image, values, full, projection: str) -> Tuple[Tuple[float, float], str]:
    """The MinIP and average rules of the module docstring."""
    if projection == "minip" and looks_like_ct(image, values):
        low, high = PRESETS["ct-minip"]
        if full[0] < high and full[1] > low:
            return (max(low, full[0]), min(high, full[1])), "CT preset ct-minip (HU)"
    if values.size:
        values = values.astype(np.float64, copy=False)
        if projection == "minip":
            median = float(np.median(values))
            spread = 1.4826 * float(np.median(np.abs(values - median)))
            high = float(np.nanmax([median - 3.0 * spread, np.percentile(values, 0.5), _cell_percentile(image, 0.5)]))
            below = values[values < high]
            if below.size:
                low = float(np.percentile(below, 0.5))
                if not high > low:
                    low = float(below.min())
                if high > low:
                    return (low, high), "histogram percentiles (MinIP)"
        else:
            averages = _axis_averages(image)
            low, high = (float(v) for v in np.percentile(averages, [1.0, 99.0]))
            if high > low:
                return (low, high), "percentiles of the average projections"
    if full[1] > full[0]:
        return full, "data range"
    return constant_window(full[0]), "constant data"


def resolve_window(image, window: WindowSpec = None, projection: str = "mip") -> Tuple[float, float]:
    """Turn a window request into (low, high).

    Parameters
    ----------
    image : vtkImageData
        The volume the window is for.
    window : None, str or sequence of two floats
        ``None`` or ``"auto"``: :func:`default_window`; ``"full"``: the data
        range; a name of :data:`PRESETS`; ``"dicom"``, ``"dicom:K"`` or
        ``"dicom:NAME"``: a window the DICOM series carries (:func:`dicom_windows`);
        or ``(low, high)``, returned as floats.
    projection : {"mip", "minip", "average"}, default: "mip"
        The method's projection (``Method.projection``): which default rule.

    Raises
    ------
    ValueError
        For an unknown name, a DICOM window the volume does not carry, or not two finite numbers.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> resolve_window(make_fixture("spheres", size=8), (0, 2))
    (0.0, 2.0)
    >>> resolve_window(make_fixture("spheres", size=8), "ct-bone")
    (-500.0, 1500.0)
    """
    if window is None:
        return default_window(image, projection)
    if isinstance(window, str):
        name = window.strip().lower()
        if name == "auto":
            return default_window(image, projection)
        if name == "full":
            low, high = data_range(image)
            return (low, high) if high > low else constant_window(low)
        if name in PRESETS:
            return PRESETS[name]
        if name.partition(":")[0] == "dicom":
            return _dicom_window(image, window.strip())
        raise ValueError(f"window must be (low, high), 'auto', 'full', 'dicom' or one of {sorted(PRESETS)}; "
                         f"got {window!r}")
    values = tuple(window)
    if len(values) != 2:
        raise ValueError(f"window must be (low, high), got {tuple(window)}")
    low, high = float(values[0]), float(values[1])
    if not (np.isfinite(low) and np.isfinite(high)):
        raise ValueError(f"window must be two finite numbers (low, high), got {values}; 'full' is the data range")
    return low, high


def parse_window(tokens: Optional[Sequence[str]]) -> WindowSpec:
    """The command line's ``--window``: ``LOW HIGH``, ``auto``, ``full``, a preset name or ``dicom[:K|:NAME]``.

    Examples
    --------
    >>> parse_window(["100", "1500"]), parse_window(["full"]), parse_window(None)
    ((100.0, 1500.0), 'full', None)
    """
    if tokens is None:
        return None
    if len(tokens) == 1:
        word = tokens[0].strip().lower()
        if word in KEYWORDS or word in PRESETS:
            return word
        if word.partition(":")[0] == "dicom":
            return tokens[0].strip()  # the name as given (matched case-insensitively)
    if len(tokens) == 2:
        try:
            return float(tokens[0]), float(tokens[1])
        except ValueError:
            pass
    raise ValueError(f"--window takes LOW HIGH, 'auto', 'full', 'dicom' or one of {', '.join(sorted(PRESETS))}; "
                     f"got {' '.join(tokens)!r}")


def _volume_and_stride(image) -> Tuple[np.ndarray, int]:
    """The scalars (first component) as a volume [k, j, i], and the stride along each axis that leaves about
    :data:`SAMPLE_LIMIT` points."""
    values = vtk_to_numpy(image.GetPointData().GetScalars())
    if values.ndim > 1:
        values = values[:, 0]
    nx, ny, nz = image.GetDimensions()
    volume = values.reshape(nz, ny, nx)
    return volume, max(1, int(np.ceil((volume.size / SAMPLE_LIMIT) ** (1.0 / 3.0))))


def _cell_percentile(image, q: float) -> float:
    """The ``q``-th percentile of the trilinear interpolant at the cell centres (the mean of each cell's 8
    corners; cells with a missing corner left out; every k-th cell along each axis: at most about
    :data:`SAMPLE_LIMIT`); NaN where there is no such cell (a single slice, every cell missing a corner).

    Rays see the interpolant, not the voxels: between the voxels of white noise it averages out, so a floor at a
    voxel percentile can lie above everything a ray meets (``np.random.rand`` drew black).
    """
    volume, stride = _volume_and_stride(image)
    shape = tuple(len(range(0, n - 1, stride)) for n in volume.shape)
    total = np.zeros(shape)
    for corner in np.ndindex(2, 2, 2):
        total += volume[tuple(slice(c, c + stride * n, stride) for c, n in zip(corner, shape))]
    total = total.ravel() / 8.0
    total = total[np.isfinite(total)]
    return float(np.percentile(total, q)) if total.size else float("nan")


def _axis_averages(image) -> np.ndarray:
    """The volume's means along each index axis (every k-th point: at most about :data:`SAMPLE_LIMIT` used)."""
    volume, stride = _volume_and_stride(image)
    volume = volume[::stride, ::stride, ::stride]
    finite = np.isfinite(volume) if np.issubdtype(volume.dtype, np.floating) else None
    parts = []
    for axis in range(3):
        if finite is None:
            parts.append(volume.mean(axis=axis, dtype=np.float64).ravel())
        else:
            count = finite.sum(axis=axis)
            total = np.where(finite, volume, 0.0).sum(axis=axis, dtype=np.float64)
            parts.append((total / np.maximum(count, 1))[count > 0].ravel())
    return np.concatenate(parts)


def _sample(image) -> np.ndarray:
    values = vtk_to_numpy(image.GetPointData().GetScalars())
    if values.ndim > 1:
        values = values[:, 0]
    if values.dtype.kind == "f":
        values = values[np.isfinite(values)]  # missing data: no part of any window
    if values.size > SAMPLE_LIMIT:
        values = values[:: -(-values.size // SAMPLE_LIMIT)]
    return values

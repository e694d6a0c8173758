"""The image a composite data set holds: a pyvista ``MultiBlock``, a ``.vtm`` or ``.vtpd`` file.

Readers and scripts hand volumes over in composite data sets: pyvista's
``pv.read`` of a ``.vtm``, ParaView's "Save Data" of a multiblock or a
partitioned data set, a simulation writing one image per rank.  Such a data
set is drawn when it holds one volume: one non-empty leaf, or pieces of one
image data grid (the same origin, spacing and direction, extents side by
side: what ParaView's ranks and VTK's extent translators cut), joined into
one image over the pieces' extents (origins a whole number of steps apart).  Anything else is a ``TypeError`` that
says what it holds and what to do.

Examples
--------
>>> from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
>>> from mipcast.data_fixtures import make_fixture
>>> blocks = vtkMultiBlockDataSet()
>>> blocks.SetBlock(0, make_fixture("spheres", size=8))
>>> one_image(blocks).GetDimensions()
(8, 8, 8)
"""
from __future__ import annotations

from typing import Optional

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkDataArray
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkDataSetAttributes, vtkImageData

from mipcast.core.camera_rays import matrix_array
from mipcast.core.errors import InputError


def leaves(data: vtkCompositeDataSet) -> list:
    """The non-empty data sets of ``data`` (every level of nesting), in order."""
    iterator = data.NewIterator()
    iterator.SkipEmptyNodesOn()
    found = []
    iterator.InitTraversal()
    while not iterator.IsDoneWithTraversal():
        leaf = iterator.GetCurrentDataObject()
        if leaf is not None and leaf.IsA("vtkDataSet") and leaf.GetNumberOfPoints() > 0:
            found.append(leaf)
        iterator.GoToNextItem()
    return found


def one_image(data: vtkCompositeDataSet, index: Optional[int] = None):
    """The one volume ``data`` holds: its only non-empty leaf, or its image pieces joined.

    Parameters
    ----------
    data : vtkCompositeDataSet
        A multiblock, partitioned or partitioned-collection data set
        (pyvista's ``MultiBlock``); not modified.
    index : int, optional
        Take its data set ``index`` (from 0, in :func:`leaves`' order: the
        non-empty ones at any depth) instead, e.g. the volume of a file that
        also holds meshes.

    Returns
    -------
    vtkDataSet
        The only leaf as it is (image data, a rectilinear grid, ...: the
        caller's checks apply), or a new ``vtkImageData`` over the union of
        the pieces' extents holding the point and cell arrays every piece has
        (of a ghost array only its HIDDEN bits: the pieces' ghost layers are
        the neighbours' own points).

    Raises
    ------
    InputError
        If ``data`` holds no data set with points, or fewer than ``index + 1``.
    TypeError
        If it holds several data sets that are not pieces of one image data
        grid (the message lists them and the fix: pick one block).

    Examples
    --------
    >>> from vtkmodules.vtkCommonDataModel import vtkPartitionedDataSet
    >>> from vtkmodules.vtkImagingCore import vtkExtractVOI
    >>> from mipcast.data_fixtures import make_fixture
    >>> whole = make_fixture("spheres", size=8)
    >>> pieces = vtkPartitionedDataSet()
    >>> for index, extent in enumerate([(0, 7, 0, 7, 0, 3), (0, 7, 0, 7, 3, 7)]):
    ...     cut = vtkExtractVOI()
    ...     cut.SetInputData(whole)
    ...     cut.SetVOI(*extent)
    ...     _ = cut.Update()
    ...     pieces.SetPartition(index, cut.GetOutput())
    >>> joined = one_image(pieces)
    >>> joined.GetExtent(), (vtk_to_numpy(joined.GetPointData().GetScalars())
    ...                      == vtk_to_numpy(whole.GetPointData().GetScalars())).all()
    ((0, 7, 0, 7, 0, 7), np.True_)
    """
    found = leaves(data)
    kind = data.GetClassName()[3:]
    if not found:
        raise InputError(f"the {kind} holds no data set with points: load or generate data first")
    if index is not None:
        if not 0 <= index < len(found):
            raise InputError(f"the {kind} holds {len(found)} data set(s) with points: pick one of 0 to "
                             f"{len(found) - 1}, not {index}")
        return found[index]
    if len(found) == 1:
        return found[0]
    if all(isinstance(leaf, vtkImageData) for leaf in found):
        joined = _joined(found)
        if joined is not None:
            return joined
    listing = ", ".join(f"{number}: {leaf.GetClassName()[3:]} of {leaf.GetNumberOfPoints()} points"
                        for number, leaf in enumerate(found[:6]))
    raise TypeError(
        f"the {kind} holds {len(found)} data sets ({listing}{', ...' if len(found) > 6 else ''}), not one "
        "volume (or pieces of one image data grid: the same spacing and direction, origins whole steps apart, "
        "extents that fill a box); draw one of them: pyvista mb[0] (or mb['name']), VTK GetBlock(0), "
        "ParaView's Extract Block, a file's read_volume(path, volume=K) or mipcast render --volume K; or "
        "resample them onto one image first (vtkResampleToImage)")


def _joined(pieces: list):
    """The image pieces of one grid joined over the union of their extents, or None if they are not such pieces.

    One grid: the same spacing and direction, and origins whose differences
    are whole steps (pyvista's ``extract_subset`` moves the origin to the
    piece's first point, VTK's ``vtkExtractVOI`` keeps it and the extent).
    """
    first = pieces[0]
    spacing, direction = np.array(first.GetSpacing()), matrix_array(first.GetDirectionMatrix())
    origin = np.array(first.GetOrigin())
    extents = []
    for piece in pieces:
        if not (np.allclose(piece.GetSpacing(), spacing, rtol=1e-9, atol=0.0)
                and np.allclose(matrix_array(piece.GetDirectionMatrix()), direction, rtol=0.0, atol=1e-9)):
            return None
        steps = direction.T @ (np.array(piece.GetOrigin()) - origin) / spacing
        if np.abs(steps - np.round(steps)).max() > 1e-6:
            return None
        extents.append(np.array(piece.GetExtent()).reshape(3, 2) + np.round(steps).astype(int)[:, None])
    extents = np.array(extents)
    whole = np.stack([extents[:, :, 0].min(axis=0), extents[:, :, 1].max(axis=0)], axis=1)
    image = vtkImageData()
    image.SetExtent(*whole.ravel().tolist())
    image.SetOrigin(origin)
    image.SetSpacing(spacing)
    image.SetDirectionMatrix(first.GetDirectionMatrix())
    if not _fill(image, pieces, whole, extents, "GetPointData", False):
        return None
    # pieces that share no layer of points leave the cells between them without values: no cell arrays then
    _fill(image, pieces, whole, extents, "GetCellData", True)
    arrays = image.GetPointData().GetNumberOfArrays() + image.GetCellData().GetNumberOfArrays()
    return image if arrays else None


def _fill(image, pieces, whole, extents, attribute: str, cells: bool):
    """Copy the arrays all ``pieces`` have (point or cell arrays) into ``image``; False (nothing copied) if
    the pieces leave a gap in the box."""
    size = whole[:, 1] - whole[:, 0] + (0 if cells else 1)
    if cells and (size < 1).any():
        return True  # a flat box has no cells to fill
    covered = np.zeros(size[::-1], dtype=bool)  # (z, y, x)
    spans = []
    for extent in extents:
        low = extent[:, 0] - whole[:, 0]
        high = extent[:, 1] - whole[:, 0] + (0 if cells else 1)
        span = tuple(slice(int(a), int(b)) for a, b in zip(low[::-1], high[::-1]))
        covered[span] = True
        spans.append(span)
    if not covered.all():
        return False
    sources = [getattr(piece, attribute)() for piece in pieces]
    target = getattr(image, attribute)()
    active = sources[0].GetScalars()
    for index in range(sources[0].GetNumberOfArrays()):
        first = sources[0].GetArray(index)
        if first is None or first.GetName() is None or first.IsA("vtkBitArray"):
            continue
        arrays = [source.GetArray(first.GetName()) for source in sources]
        if any(array is None or array.GetNumberOfComponents() != first.GetNumberOfComponents()
               or array.GetDataType() != first.GetDataType() for array in arrays):
            continue  # not in every piece alike: left out
        components = first.GetNumberOfComponents()
        joined = vtkDataArray.CreateDataArray(first.GetDataType())
        joined.SetName(first.GetName())
        joined.SetNumberOfComponents(components)
        joined.SetNumberOfTuples(int(np.prod(size)))
        out = vtk_to_numpy(joined).reshape(tuple(size[::-1]) + (components,))
        for span, array in zip(spans, arrays):
            shape = tuple(s.stop - s.start for s in span) + (components,)
            out[span] = vtk_to_numpy(array).reshape(shape)
        if first.GetName() == vtkDataSetAttributes.GhostArrayName():
            # a piece's ghost layers are another piece's own points and cells: in the whole only what hides
            # them stays (HIDDENPOINT, HIDDENCELL: blanking), not the DUPLICATE... bits of the pieces' overlaps
            out &= np.array(vtkDataSetAttributes.HIDDENCELL if cells else vtkDataSetAttributes.HIDDENPOINT, out.dtype)
            if not out.any():
                continue
        if active is not None and first.GetName() == active.GetName():
            target.SetScalars(joined)
        else:
            target.AddArray(joined)
    return True

"""Exact MIP of a volume split across MPI ranks: each rank renders its brick, a MAX reduction composites.

ParaView composites volumes by ordered alpha blending, which is wrong for
MIP. MIP needs no order: the maximum of the bricks' maxima is the maximum.
Here each rank renders its brick (a vtkImageData whose extent is a part of
the whole extent, sharing at least one layer of points with its neighbours)
with the WHOLE volume's camera into a float readout (data units), and one
``MPI_Allreduce(MAX)`` over float32 images makes the whole volume's float
image on every rank; the colour is applied after the reduction, through the
volume property's transfer functions.

- Analytic MIP (cell walking): a cell lies entirely in one brick (or in two,
  on a shared layer), so the maximum over the bricks is the maximum over the
  whole volume's cells; the ``global_cells`` piece walks the whole volume's
  ray over the brick's cells, every plane parameter from its index, so N
  ranks give the 1-rank floats bit for bit.
- Sampled MIP: each brick takes the whole volume's samples, bit for bit
  (the ``global_phase`` shader piece): each pixel's ray is cast in the
  whole volume's point-index space from uniforms that are the same on
  every rank (:func:`ray_uniforms`), sample k sits at the whole box's entry
  (or, the camera inside the volume, VTK's near-plane cap beyond it:
  :func:`mipcast.core.camera_rays.near_cap`) + (1 + k) steps and is
  interpolated by hand from its cell's 8 points (the
  brick holding the cell takes it), and the readout is normalised with the
  whole range: N ranks give the 1-rank float image bit for bit (measured on
  2 and 4 ranks, every split).
- DEMIP (``demip``, ``demip_two_pass``: ``distributed="demip"``), in two
  reductions, exactly the single-process definition: phase 1 is the MAX
  reduction of the sampled MIP above (DEMIP's maximum); phase 2 hands that
  whole-ray maximum back to every rank's GPU as a float texture, each rank
  marches its brick's share of the whole volume's samples to the first
  sample of the same material as the GLOBAL maximum and reads out its
  whole-ray index (:class:`mipcast.mappers.demip_brick.DEMIPBrickDepthMapper`),
  and a MIN reduction gives the whole ray's first same-material sample.
  Its depth (normalised over the WHOLE volume's box, every depth mode),
  Eq. 1, the colour sphere and pseudo-chromadepth are applied on the CPU
  with :mod:`mipcast.core.demip_depth`, the maths of the float64 reference.
  A slab (``slab_thickness`` > 0) clips both phases of every rank to the
  same global slab, depth normalised over the box's part inside it.
- DEMIP's ordered projections (``projection`` ``"lmip"``, ``"attenuated"``,
  ``"mida"``, with or without the slab) depend on the order along the whole
  ray: the ranks draw their bricks one after another, front to back, as the
  render view's ranks do (:mod:`mipcast.mappers.rank_ordered`, through
  :func:`mipcast.mappers.rank_composite.compose` in the renderer's
  StartEvent, on a hidden DEMIP mapper of the brick), with
  :meth:`DistributedView.reduce` (``comm.Allreduce``, float64) as the
  reduction: at turn k the k-th brick's rank continues the scan from the
  state so far and a SUM hands the new state to every rank.  LMIP's and
  attenuated MIP's value and LMIP's depth come back as floats; MIDA gives
  the picture only.  A rank failing in its turn makes every rank raise at
  the same collective, with the reason.

The method table's ``distributed`` entry names the route (:data:`ROUTES`);
other methods are refused with a message. mpi4py provides the communicator
(``from mpi4py import MPI``; inside ``pvbatch --symmetric`` too); without
mpi4py a job of one process runs (:class:`OneRank`).

Examples
--------
>>> split_extents((0, 63, 0, 63, 0, 63), 2, axis=0)
[(0, 31, 0, 63, 0, 63), (31, 63, 0, 63, 0, 63)]
>>> split_extents((0, 63, 0, 31, 0, 31), 4)
[(0, 31, 0, 31, 0, 15), (0, 31, 0, 31, 15, 31), (31, 47, 0, 31, 0, 31), (47, 63, 0, 31, 0, 31)]
"""
from __future__ import annotations

import contextlib
import sys
import time
import traceback
from typing import List, Optional, Sequence, Tuple

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkImagingCore import vtkImageClip

from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkRenderingCore import vtkVolume

from mipcast import methods
from mipcast.core.camera_rays import placed
from mipcast.core.errors import InputError
from mipcast.core.object_state import object_state
from mipcast.core.parameter_tables import DEMIP_SETTINGS
from mipcast.core.parameters import set_parameters
from mipcast.core.prepare import prepare_scalars
from mipcast.core.validation import check_choice
from mipcast.mappers.brick_rays import (global_texture_box, push_interpolation, ray_uniforms, set_brick_uniforms,  # noqa: F401
                                          set_ray_uniforms)
from mipcast.mappers.clip_uniforms import slab_of
from mipcast.mappers.demip_brick import DEMIPBrickDepthMapper, first_match_index
from mipcast.mappers.demip_composite import demip_composite, demip_picture  # noqa: F401  (demip_picture: public here)
from mipcast.mappers.float_readout import read_normalised, texture_scale
from mipcast.mappers.rank_ordered import ORDERED
from mipcast.offscreen import OffscreenView, set_view

Extent = Tuple[int, int, int, int, int, int]

#: Reduced values below this are "no sample" (a brick's empty ray), not data.
_NO_SAMPLE = -1.0e20


def split_extents(whole: Sequence[int], count: int, axis: Optional[int] = None,
                  ghost: int = 0) -> List[Extent]:
    """Split ``whole`` into ``count`` bricks that share a layer of points (plus ``ghost`` layers).

    Parameters
    ----------
    whole : sequence of 6 int
        The whole extent (x0, x1, y0, y1, z0, z1).
    count : int
        Number of bricks (>= 1).
    axis : int, optional
        0, 1 or 2: slabs along that axis.  Default: a D3-style recursive
        bisection (the longest axis of each part is halved, the ranks split
        in proportion).
    ghost : int, default: 0
        Extra layers of points each brick takes beyond the shared layer.

    Returns
    -------
    list of tuple
        One extent per brick, in rank order.  Adjacent bricks share the
        point layer at their common face, so every cell lies in a brick.

    Examples
    --------
    >>> split_extents((0, 9, 0, 9, 0, 9), 3, axis=2)
    [(0, 9, 0, 9, 0, 3), (0, 9, 0, 9, 3, 6), (0, 9, 0, 9, 6, 9)]
    >>> split_extents((0, 9, 0, 9, 0, 9), 2, axis=1, ghost=1)
    [(0, 9, 0, 5, 0, 9), (0, 9, 3, 9, 0, 9)]
    """
    whole = tuple(int(v) for v in whole)
    if len(whole) != 6 or any(whole[2 * a + 1] < whole[2 * a] for a in range(3)):
        raise ValueError(f"whole extent must be (x0, x1, y0, y1, z0, z1) with x0 <= x1 ..., got {whole}")
    if int(count) < 1:
        raise ValueError(f"count must be at least 1, got {count}")
    if axis is not None and axis not in (0, 1, 2):
        raise ValueError(f"axis must be 0, 1, 2 or None (D3-style bisection), got {axis!r}")
    if int(ghost) < 0:
        raise ValueError(f"ghost must be >= 0, got {ghost}")
    bricks = _slabs(whole, int(count), axis) if axis is not None else _bisect(whole, int(count))
    out = []
    for brick in bricks:
        grown = []
        for a in range(3):
            grown += [max(whole[2 * a], brick[2 * a] - ghost), min(whole[2 * a + 1], brick[2 * a + 1] + ghost)]
        out.append(tuple(grown))
    return out


def _slabs(whole, count, axis):
    low, high = whole[2 * axis], whole[2 * axis + 1]
    cells = high - low
    if cells < count:
        raise ValueError(f"cannot split {cells} cells along axis {axis} into {count} bricks")
    cuts = [low + (cells * j) // count for j in range(count + 1)]
    bricks = []
    for j in range(count):
        brick = list(whole)
        brick[2 * axis], brick[2 * axis + 1] = cuts[j], cuts[j + 1]
        bricks.append(tuple(brick))
    return bricks


def _bisect(whole, count):
    if count == 1:
        return [tuple(whole)]
    axis = max(range(3), key=lambda a: (whole[2 * a + 1] - whole[2 * a], a))
    left = count // 2
    low, high = whole[2 * axis], whole[2 * axis + 1]
    if high - low < 2:
        raise ValueError(f"cannot split the extent {whole} into {count} bricks")
    cut = low + ((high - low) * left) // count
    first, second = list(whole), list(whole)
    first[2 * axis + 1] = cut
    second[2 * axis] = cut
    return _bisect(tuple(first), left) + _bisect(tuple(second), count - left)


def extract_piece(image, extent: Sequence[int]):
    """The brick ``extent`` of ``image``: a new vtkImageData keeping the whole volume's indices.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> extract_piece(make_fixture("vessels", size=16), (0, 15, 0, 15, 4, 9)).GetExtent()
    (0, 15, 0, 15, 4, 9)
    """
    clip = vtkImageClip()
    clip.SetInputData(image)
    clip.SetOutputWholeExtent(*[int(v) for v in extent])
    clip.ClipDataOn()
    clip.Update()
    piece = vtkImageData()
    piece.DeepCopy(clip.GetOutput())
    piece.SetDirectionMatrix(image.GetDirectionMatrix())  # VTK 9.2's vtkImageClip (ParaView's) drops it
    return piece


class OneRank:
    """The communicator of a job of one process, where mpi4py is missing: reductions are the identity.

    Examples
    --------
    >>> OneRank().rank, OneRank().size
    (0, 1)
    """

    rank = 0
    size = 1

    def Abort(self, code: int = 1) -> None:  # noqa: N802  (mpi4py's name)
        """End this process (there is no other)."""
        import os

        os._exit(code)


def world_communicator():
    """``mpi4py.MPI.COMM_WORLD``; a :class:`OneRank` where mpi4py is not installed.

    Examples
    --------
    >>> world_communicator().rank
    0
    """
    try:
        from mpi4py import MPI
    except ImportError:
        return OneRank()
    return MPI.COMM_WORLD


def _reduce_inplace(comm, array: np.ndarray, op: str) -> np.ndarray:
    """``Allreduce(IN_PLACE, array, op)`` (``"max"`` or ``"min"``); identity for :class:`OneRank`."""
    if not isinstance(comm, OneRank):
        from mpi4py import MPI

        comm.Allreduce(MPI.IN_PLACE, array, op=MPI.MAX if op == "max" else MPI.MIN)
    return array


def whole_extent(piece, comm) -> Extent:
    """The extent the ranks' bricks span together (an MPI reduction of the bricks' extents)."""
    extent = piece.GetExtent()
    lows = _reduce_inplace(comm, np.array(extent[0::2], dtype=np.int64), "min")
    highs = _reduce_inplace(comm, np.array(extent[1::2], dtype=np.int64), "max")
    return tuple(int(v) for pair in zip(lows, highs) for v in pair)


def whole_range(piece, comm) -> Tuple[float, float, bool]:
    """The finite range of the drawn values (several components: their magnitude) over every rank's brick, and
    whether any brick holds missing (NaN/Inf) values.

    Examples
    --------
    >>> import numpy as np
    >>> from mipcast.data_fixtures.synthetic import image_from_array
    >>> values = np.arange(8.0).reshape(2, 2, 2); values[0, 0, 0], values[1, 1, 1] = np.nan, np.inf
    >>> whole_range(image_from_array(values), OneRank())
    (1.0, 6.0, True)
    """
    # what is drawn (mipcast.core.prepare: a component or the magnitude, int64 as float64), validated; the range
    # given only lets a brick of missing values alone through
    prepared = prepare_scalars(piece, whole_range=(0.0, 1.0))
    seen = prepared.missing < prepared.values.size
    low, high = (prepared.low, prepared.high) if seen else (np.inf, -np.inf)
    ends = _reduce_inplace(comm, np.array([-low, high, float(prepared.missing > 0)]), "max")
    return float(-ends[0]), float(ends[1]), bool(ends[2] > 0.0)


def _whole_stub(piece, extent):
    """A scalar-less image with the whole volume's geometry (for the camera and the bounds)."""
    stub = vtkImageData()
    stub.SetExtent(*extent)
    stub.SetOrigin(piece.GetOrigin())
    stub.SetSpacing(piece.GetSpacing())
    stub.SetDirectionMatrix(piece.GetDirectionMatrix())
    return stub


class DistributedView:
    """One rank's part of an exact distributed MIP: its brick, the whole volume's camera.

    Every rank of ``comm`` constructs one with its own brick and the same
    other arguments, then calls :meth:`float_image` or :meth:`screenshot`
    together (they are collective).

    Parameters
    ----------
    piece : vtkImageData
        This rank's brick (extent within the whole extent; bricks share at
        least one layer of points, e.g. :func:`split_extents`, ParaView's
        readers, RedistributeDataSet with ghost cells).
    method : str, default: "mip"
        A method whose table entry has a ``distributed`` route (:data:`ROUTES`):
        ``mip``, ``analytic`` (``"max"``), ``demip``, ``demip_two_pass`` (``"demip"``,
        every projection: LMIP, attenuated MIP and MIDA rank after rank, front to back).
    size, view, sample_distance
        As :class:`mipcast.offscreen.OffscreenView`, for the whole volume
        (the camera frames the whole volume; default sample distance: the
        smallest spacing).
    window : tuple of float or "full", default: "full"
        Grey window in data units; ``"full"`` the whole volume's range.
    comm : mpi4py communicator, optional
        Default ``MPI.COMM_WORLD``.
    max_voxels : int, optional
        A rank's texture budget: a brick with more points is refused with a
        message (the whole volume then needs more ranks).
    time_wait : bool, default: False
        Wait for every rank before the reduction (a barrier), so that
        ``last_times["composite"]`` is the reduction alone and
        ``last_times["wait"]`` the load imbalance (benchmarks).
    **settings
        The method's parameters, as :func:`mipcast.core.parameters.set_parameters`.

    Examples
    --------
    Under ``mpiexec -n 2 pvbatch --symmetric script.py`` (each rank):

    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("vessels", size=32)
    >>> comm = world_communicator()          # one rank here: the whole volume
    >>> brick = extract_piece(image, split_extents(image.GetExtent(), comm.size, 2)[comm.rank])
    >>> view = DistributedView(brick, "analytic", size=(32, 32), comm=comm)
    >>> view.float_image().shape
    (32, 32)
    """

    def __init__(self, piece, method: str = "mip", size=(256, 256), view: str = "oblique",
                 sample_distance: Optional[float] = None, window="full", comm=None,
                 max_voxels: Optional[int] = None, time_wait: bool = False, **settings) -> None:
        entry = methods.METHODS[check_choice("method", method, tuple(methods.METHODS))]
        if entry.distributed not in ROUTES:
            able = [m.name for m in methods.METHODS.values() if m.distributed in ROUTES]
            raise ValueError(f"method {method!r} has no exact distributed composite yet; "
                             f"use one of {able}, or render the whole volume on one rank")
        #: The composite route (:data:`ROUTES`), from the method table's ``distributed``.
        self.route = entry.distributed
        self._method_mapper = entry.factory()  # not drawn: it validates the settings as the method does
        self.comm = world_communicator() if comm is None else comm
        self.whole_extent = whole_extent(piece, self.comm)
        points = int(np.prod([piece.GetExtent()[2 * a + 1] - piece.GetExtent()[2 * a] + 1 for a in range(3)]))
        if max_voxels is not None and points > int(max_voxels):
            raise ValueError(f"rank {self.comm.rank}: brick {piece.GetExtent()} has {points} points, over this "
                             f"rank's texture budget of {int(max_voxels)}: run more ranks (mpiexec -n) "
                             "or split the volume finer")
        low, high, missing = whole_range(piece, self.comm)
        if not high >= low:  # every rank alike
            raise InputError("every brick's values are NaN/Inf (missing): there is nothing to draw; check the data "
                             "or choose another array")
        #: The whole volume's finite scalar range (every rank's readouts are normalised with it).
        self.data_range = (low, high)
        #: Whether any brick holds missing values: then every brick fills them as the whole volume does (a brick
        #: may then hold missing values only).
        self.missing = missing  # (the brick was validated by whole_range)
        if isinstance(window, str):
            if window != "full":
                raise ValueError(f"window must be (low, high) or 'full', got {window!r}")
            window = self.data_range
        self.stub = _whole_stub(piece, self.whole_extent)
        self.piece_extent = tuple(piece.GetExtent())
        self._texture_scale = texture_scale(piece.GetPointData().GetScalars())
        self._brick_range = piece.GetPointData().GetScalars().GetRange(0)
        self._scalar_type = piece.GetPointData().GetScalars().GetDataTypeAsString()
        if sample_distance is None:
            sample_distance = min(abs(s) for s in piece.GetSpacing())
        self.sample_distance = float(sample_distance)
        first_method = ROUTES[self.route]["first_pass"] or entry.name
        self.local = OffscreenView(piece, first_method, size, "front", sample_distance, tuple(window),
                                   whole_range=self.data_range if missing else None)
        set_view(self.local.renderer, self.stub, view)
        self.window = self.local.window
        texture_min, texture_max = global_texture_box(piece.GetExtent(), self.whole_extent)
        self._global_box = (texture_min, texture_max)
        _set_global_box(self.local.mapper, self.local.volume, self._global_box)
        self._set_static_uniforms(self.local.volume)
        #: Phase 2 of the ``"demip"`` route (None for ``"max"``).
        self.depth_mapper = None
        #: The DEMIP mapper of the ordered projections (``"demip"`` route, made when one is set).
        self.ordered_mapper = None
        self._piece = piece
        if self.route == "demip":
            self._make_depth_pass(piece, settings)
        elif settings:
            set_parameters(self.local.mapper, **settings)
        self.time_wait = bool(time_wait)
        #: Seconds of the last frame: ``render`` (this rank's brick), ``wait`` (for the
        #: other ranks, with ``time_wait``), ``composite`` (the reduction).
        self.last_times = {"render": 0.0, "wait": 0.0, "composite": 0.0}

    def _make_depth_pass(self, piece, settings) -> None:
        """The ``"demip"`` route's phase-2 mapper: DEMIP's settings, this brick, the whole volume's samples."""
        mapper = self.depth_mapper = DEMIPBrickDepthMapper()
        self._fill_as_whole(mapper)
        volume = self.depth_volume = self._hidden_volume(mapper, piece)
        self.set_parameters(**settings)
        _set_global_box(mapper, volume, self._global_box)
        self._set_static_uniforms(volume)

    def _fill_as_whole(self, mapper) -> None:
        """Where any brick holds missing values, ``mapper`` fills them as the whole volume does (the same fill and
        missing threshold on every rank: :func:`mipcast.core.prepare.missing_fill` of the whole finite range)."""
        if self.missing:
            mapper.GetInputPreparer().SetWholeRange(self.data_range)

    def _set_static_uniforms(self, volume) -> None:
        """The global_phase piece's whole/brick index boxes, spacing, step and the whole range's normalisation."""
        uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
        set_brick_uniforms(uniforms, self.whole_extent, self.piece_extent, self.stub.GetSpacing(),
                           self.sample_distance)
        low, high = self.data_range
        brick_low, brick_high = self._brick_range
        raw_per_data = _RAW_PER_DATA.get(self._scalar_type)
        if high > low and raw_per_data is not None:
            # VTK's normalisation of the raw texel value with the WHOLE range: the same on every rank
            scale, bias = self._texture_scale / (raw_per_data * (high - low)), -low / (high - low)
            uniforms.SetUniform3f("u_mc_globalNorm", [1.0, scale, bias])
            # the missing threshold on the same scale as the samples (MIPVolumeMapper._missing_below)
            object_state(volume.GetMapper())["global_normalisation"] = (scale * raw_per_data, bias)
        elif high > low and brick_high > brick_low:
            # the brick's normalised scalar -> the WHOLE range's (float32 readouts on one grid)
            uniforms.SetUniform3f("u_mc_globalNorm", [2.0, (brick_high - brick_low) / (high - low),
                                                      (brick_low - low) / (high - low)])


    def _placed(self):
        """The whole volume as the view's volume's matrix places it (:func:`mipcast.core.camera_rays.placed`).

        ``view.local.volume`` may carry a matrix (``SetUserMatrix``, position,
        orientation, scale, origin; the same on every rank): the hidden phase
        volumes take it too, and the whole volume's rays, DEMIP's depth and the
        ordered turns are cast in its index space as it places it.
        """
        matrix = self.local.volume.GetMatrix()
        for name in ("depth_volume", "ordered_volume"):
            hidden = getattr(self, name, None)
            if hidden is not None:
                own = hidden.GetUserMatrix()
                if own is None or any(own.GetElement(r, c) != matrix.GetElement(r, c)
                                      for r in range(4) for c in range(4)):
                    copy = vtkMatrix4x4()
                    copy.DeepCopy(matrix)
                    hidden.SetUserMatrix(copy)
        return placed(self.stub, matrix)

    def _push_rays(self) -> None:
        """This frame's rays (the camera may have moved): the same uniforms on every rank."""
        width, height = self.local.size
        values = ray_uniforms(self._placed(), self.camera, (width, height))
        volumes = [self.local.volume] + ([self.depth_volume] if self.depth_mapper is not None else [])
        for volume in volumes:
            set_ray_uniforms(volume.GetShaderProperty().GetFragmentCustomUniforms(), values)
            push_interpolation(volume)

    def set_parameters(self, **settings) -> None:
        """Change the method's parameters (every rank alike), as :func:`mipcast.core.parameters.set_parameters`."""
        if self.depth_mapper is None:
            set_parameters(self.local.mapper, **settings)
            return
        # the method's own mapper checks the settings first (two-pass DEMIP refuses the ordered projections)
        set_parameters(self._method_mapper, **settings)
        set_parameters(self.depth_mapper, **settings)
        values = self.demip_parameters()
        # phase 1 clips with the same slab (its default centre and normal follow the same camera)
        slab = {name: values[name] for name in ("slab_thickness", "slab_centre", "slab_normal")}
        set_parameters(self.local.mapper, **slab)
        if values["projection"] in ORDERED or self.ordered_mapper is not None:
            mapper = self._ordered_pass()
            set_parameters(mapper, **values)

    def _ordered_pass(self):
        """The DEMIP mapper on this brick that :mod:`mipcast.mappers.rank_ordered` draws the ordered
        projections from (hidden: rank_composite renders its private brick mappers in the StartEvent)."""
        if self.ordered_mapper is None:
            from mipcast.mappers.demip import DEMIPVolumeMapper

            mapper = self.ordered_mapper = DEMIPVolumeMapper()
            mapper.SetAutoAdjustSampleDistances(False)
            self._fill_as_whole(mapper)
            self.ordered_volume = self._hidden_volume(mapper, self._piece)
        return self.ordered_mapper

    def _hidden_volume(self, mapper, piece) -> vtkVolume:
        """A hidden volume of this brick in the renderer, drawn by ``mapper`` at the view's sample distance."""
        mapper.SetInputData(piece)
        mapper.SetSampleDistance(self.local.sample_distance)
        mapper.SetUseJittering(False)
        volume = vtkVolume()
        volume.SetProperty(self.local.volume.GetProperty())
        mapper.Attach(volume)
        volume.VisibilityOff()
        self.local.renderer.AddVolume(volume)
        return volume

    def reduce(self, array: np.ndarray, op: str) -> np.ndarray:
        """``comm.Allreduce`` as the ``reduce(array, op)`` of :mod:`mipcast.mappers.rank_composite`:
        float64, ``op`` ``"max"``, ``"min"`` or ``"sum"`` (the identity on :class:`OneRank`)."""
        values = np.array(array, dtype=np.float64)  # a copy: nothing the caller passed is modified
        if not isinstance(self.comm, OneRank):
            from mpi4py import MPI

            ops = {"max": MPI.MAX, "min": MPI.MIN, "sum": MPI.SUM}
            self.comm.Allreduce(MPI.IN_PLACE, values, op=ops[op])
        return values

    def _ordered_frame(self) -> np.ndarray:
        """Collective: LMIP / attenuated MIP / MIDA over the ranks, turn by turn front to back
        (:func:`mipcast.mappers.rank_composite.compose`); the premultiplied RGBA, top row first."""
        mapper, volume = self.ordered_mapper, self.ordered_volume
        direction = self.stub.GetDirectionMatrix()
        whole = (tuple(self.whole_extent), self.stub.GetOrigin(), self.stub.GetSpacing(),
                 [direction.GetElement(i, j) for i in range(3) for j in range(3)])
        out = {}

        def start(renderer, event):
            from mipcast.mappers import rank_composite

            out["result"] = rank_composite.compose(mapper, volume, renderer, self._piece, whole, self.reduce,
                                                   "demip", rank=(self.comm.rank, self.comm.size))

        self._placed()  # the ordered turns' volume takes the view's matrix (rank_composite places the whole by it)
        renderer = self.local.renderer
        tag = renderer.AddObserver("StartEvent", start)
        self.local.volume.VisibilityOff()
        # vtkCamera.DeepCopy keeps the camera's old MTime, and VTK caches the camera's matrices on it: the
        # private brick renders at the StartEvent (before VTK's own camera updates) would use the last view's
        self.camera.Modified()
        try:
            self.local.render_window.Render()
        finally:
            renderer.RemoveObserver(tag)
            self.local.volume.VisibilityOn()
        if "result" not in out:
            raise RuntimeError(f"rank {self.comm.rank}: the ordered DEMIP frame did not run (no renderer start)")
        rgba, problem = out["result"]
        if rgba is None:
            # every rank gets here at the same collective (rank_ordered flags failures in its reductions)
            raise RuntimeError(f"rank {self.comm.rank} of {self.comm.size}: DEMIP projection "
                               f"{self.demip_parameters()['projection']!r} over the ranks failed: "
                               f"{problem or 'no rank has data'}")
        return np.asarray(rgba, dtype=np.float64)

    def demip_parameters(self) -> dict:
        """The DEMIP settings of the ``"demip"`` route (name -> value, from the phase-2 mapper)."""
        if self.depth_mapper is None:
            raise ValueError(f"the {self.route!r} route has no DEMIP parameters")
        return {p.name: getattr(self.depth_mapper, p.getter)() for p in DEMIP_SETTINGS}

    @property
    def camera(self):
        """This rank's vtkCamera (the same on every rank)."""
        return self.local.camera

    def _local_float(self) -> np.ndarray:
        """This rank's float readout in data units: on the whole range's grid where global_phase draws."""
        mapper = self.local.mapper
        low, high = self.data_range
        pieces = mapper.GetShaderPieces()
        if "global_phase" not in pieces and "global_cells" not in pieces:
            return self.local.float_image()  # the brick's own normalisation
        normalised = read_normalised(self.local.render_window, mapper)
        if high > low and self._brick_range[1] > self._brick_range[0]:
            return ((low + normalised * (high - low)) / self._texture_scale).astype(np.float32)
        scalars = mapper.GetRenderedInput().GetPointData().GetScalars()
        return render_float_units(normalised, scalars)

    def _check_jittering(self) -> None:
        """Refuse VTK's jittering on the view's mapper where the ranks sample: their samples sit at the whole
        volume's fixed positions (global_phase), not at a jittered process's (every rank raises alike).

        Examples
        --------
        >>> from mipcast.data_fixtures import make_fixture
        >>> view = DistributedView(make_fixture("vessels", size=16), "mip", size=(16, 16), comm=OneRank())
        >>> view.local.mapper.SetUseJittering(True)
        >>> view.float_image()
        Traceback (most recent call last):
        ValueError: rank 0: jittering (SetUseJittering(True)) cannot be composited exactly over the ranks: ...
        """
        mapper = self.local.mapper
        if mapper.GetUseJittering() and "global_phase" in mapper.GetShaderPieces():
            raise ValueError(f"rank {self.comm.rank}: jittering (SetUseJittering(True)) cannot be composited "
                             "exactly over the ranks: each rank takes the whole volume's samples at fixed positions; "
                             "turn it off (view.local.mapper.SetUseJittering(False)) or use a cell-walking method "
                             "(analytic)")

    def float_image(self) -> np.ndarray:
        """Collective: the whole volume's float image (data units, NaN = miss), on every rank."""
        self._check_jittering()
        start = time.perf_counter()
        self._push_rays()
        local = self._local_float()
        #: This rank's own float image of its brick (the last frame), before the reduction.
        self.last_local = local
        middle = time.perf_counter()
        if self.time_wait and not isinstance(self.comm, OneRank):
            self.comm.Barrier()
        ready = time.perf_counter()
        values = np.where(np.isnan(local), -np.inf, local).astype(np.float32)
        _reduce_inplace(self.comm, values, "max")
        self.last_times = {"render": middle - start, "wait": ready - middle,
                           "composite": time.perf_counter() - ready}
        return np.where(values < _NO_SAMPLE, np.nan, values).astype(np.float32)

    def first_match(self, values: Optional[np.ndarray] = None) -> np.ndarray:
        """Collective (``"demip"`` route): each pixel's whole-ray index of the first same-material sample.

        Phase 2: every rank's brick against the GLOBAL maximum ``values``
        (default: a new :meth:`float_image`), then a MIN reduction.  Sample
        k sits at the whole ray's start (box entry or near-plane cap) + (1 + k) sample distances; +inf
        where the ray has no DEMIP term.
        """
        if self.depth_mapper is None:
            raise ValueError(f"the {self.route!r} route has no same-material search")
        if self._ordered_projection():
            raise ValueError(f"projection {self.depth_mapper.GetProjection()!r} is composited turn by turn "
                             "(demip_image); first_match is the MIN reduction of projection 'mip' only")
        if values is None:
            values = self.float_image()
        self.local.volume.VisibilityOff()
        self.depth_volume.VisibilityOn()
        try:
            self._push_rays()
            found = first_match_index(self.local.render_window, self.depth_mapper, values, self.data_range)
        finally:
            self.depth_volume.VisibilityOff()
            self.local.volume.VisibilityOn()
        return _reduce_inplace(self.comm, np.ascontiguousarray(found, dtype=np.float64), "min")

    def demip_image(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Collective (``"demip"`` route): (maximum, depth, straight RGB in [0, 1]), float64, top row first.

        The maximum in data units (NaN: miss), the depth of the first
        same-material sample in [0, 1] (NaN: no DEMIP term; normalised over
        the whole volume's box, the table's depth mode) and the final
        straight colour (Eq. 1, sphere, chromadepth where there is a term,
        the transfer functions' colour of the maximum elsewhere; 0 on misses).
        The ordered projections, turn by turn over the ranks: LMIP's value
        and depth, attenuated MIP's value (depth NaN: no DEMIP term), MIDA's
        colour (value and depth NaN); :attr:`last_rgba` holds the
        composite's premultiplied RGBA.
        Raises RuntimeError (on every rank alike) where a rank failed in the
        ordered composite.

        Examples
        --------
        >>> from mipcast.data_fixtures import make_fixture
        >>> view = DistributedView(make_fixture("vessels", size=16), "demip", size=(16, 16), comm=OneRank(),
        ...                        projection="attenuated")
        >>> values, depth, rgb = view.demip_image()
        >>> bool(np.isfinite(values).any()), bool(np.isnan(depth).all()), rgb.shape
        (True, True, (16, 16, 3))
        """
        if self._ordered_projection():
            self._check_jittering()
            rgba = self._ordered_frame()
            floats = object_state(self.ordered_mapper).get("rank_ordered_floats", {})
            nan = np.full(rgba.shape[:2], np.nan)
            alpha = rgba[..., 3:]
            self.last_rgba = rgba
            straight = np.where(alpha > 0.0, rgba[..., :3] / np.where(alpha > 0.0, alpha, 1.0), 0.0)
            return (np.asarray(floats.get("value", nan), dtype=np.float64),
                    np.asarray(floats.get("depth", nan), dtype=np.float64), straight)
        values = self.float_image()
        index = self.first_match(values)
        depth, rgb = demip_composite(self._placed(), self.camera, self.sample_distance, values, index,
                                     self.demip_parameters(), self.local.volume.GetProperty(),
                                     slab=slab_of(self.depth_mapper, self.camera))
        return values.astype(np.float64), depth, rgb

    def _ordered_projection(self) -> bool:
        """Whether this frame's DEMIP projection is an ordered one (LMIP, attenuated MIP, MIDA)."""
        return self.depth_mapper is not None and self.depth_mapper.GetProjection() in ORDERED

    def images(self) -> dict:
        """Collective: the route's float images by name (top row first), for shipping to a client.

        ``"mip_value"`` (the maximum, data units, NaN = miss) on every route;
        the ``"demip"`` route adds ``"demip_depth"`` (NaN: no DEMIP term) and
        the final straight colour ``"demip_red"``, ``"demip_green"``,
        ``"demip_blue"`` (in [0, 1]; :func:`demip_picture` makes the 8-bit picture).
        The ordered projections add ``"demip_alpha"``, the composite's opacity
        (the picture is the straight colour times it: MIDA's ``"mip_value"``
        and ``"demip_depth"`` are NaN).
        """
        if self.route != "demip":
            return {"mip_value": self.float_image()}
        values, depth, rgb = self.demip_image()
        out = {"mip_value": values.astype(np.float32), "demip_depth": depth, "demip_red": rgb[..., 0],
               "demip_green": rgb[..., 1], "demip_blue": rgb[..., 2]}
        if self._ordered_projection():
            out["demip_alpha"] = self.last_rgba[..., 3].copy()
        return out

    def depth_image(self) -> np.ndarray:
        """Collective (``"demip"`` route): the DEMIP depth per pixel (NaN: no term), as ``render_depth``."""
        return self.demip_image()[1]

    def screenshot(self) -> np.ndarray:
        """Collective: the picture (uint8 RGB, top row first): the reduced float image coloured."""
        if self.route == "demip":
            values, _, rgb = self.demip_image()
            if self._ordered_projection():  # the composite's premultiplied colour (MIDA has no single value)
                return np.clip(np.rint(self.last_rgba[..., :3] * 255.0), 0, 255).astype(np.uint8)
            return demip_picture(values, rgb, self.local.volume.GetProperty())
        return colour(self.float_image(), self.local.volume.GetProperty())


#: Raw texel value per data unit of the scalar types VTK uploads as they are (8-bit ones as
#: normalised integers): their brick textures hold the same bits on every rank.
_RAW_PER_DATA = {"float": 1.0, "double": 1.0, "unsigned char": 1.0 / 255.0, "char": 1.0 / 127.0,
                 "signed char": 1.0 / 127.0}


def render_float_units(normalised: np.ndarray, scalars) -> np.ndarray:
    """A readout (VTK's normalised scalar of ``scalars``) in data units, float32."""
    from mipcast.mappers.float_readout import to_data_units

    return to_data_units(normalised, scalars).astype(np.float32)


#: The distributed composites, by the method table's ``distributed`` value:
#: ``first_pass`` is the method each rank renders for the MAX reduction
#: (None: the method itself).
ROUTES = {
    "max": {"first_pass": None, "doc": "the MAX reduction of the bricks' float readouts"},
    "demip": {"first_pass": "mip",
              "doc": "MAX of the bricks' sampled MIP, then MIN of the whole-ray index of the first sample of "
                     "the global maximum's material; depth, Eq. 1 and sphere on the CPU"},
}


def _set_global_box(mapper, volume, box) -> None:
    """A brick's mapper takes the whole volume's sample positions (the ``global_phase`` piece)."""
    object_state(mapper)["global_box"] = box
    uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
    uniforms.SetUniform3f("u_mc_globalTexMin", box[0])
    uniforms.SetUniform3f("u_mc_globalTexMax", box[1])
    mapper.Modified()


def colour(values: np.ndarray, volume_property) -> np.ndarray:
    """Colour a float image (data units, NaN = miss) as mipcast's MIP does, over a black background.

    The colour and scalar-opacity transfer functions of ``volume_property``
    at each value, premultiplied by the opacity.

    Examples
    --------
    >>> from mipcast.offscreen import grey_property
    >>> colour(np.array([[0.0, 0.5, np.nan]]), grey_property((0.0, 1.0)))[0, :, 0].tolist()
    [0, 128, 0]
    """
    values = np.asarray(values, dtype=np.float64)
    hit = ~np.isnan(values)
    flat = np.where(hit, values, 0.0).ravel()
    scalars = numpy_to_vtk(flat, deep=True)
    rgb = vtk_to_numpy(volume_property.GetRGBTransferFunction().MapScalars(scalars, 0, -1))[:, :3]
    opacity_function = volume_property.GetScalarOpacity()
    opacity = np.array([opacity_function.GetValue(v) for v in flat])
    out = rgb.astype(np.float64) * opacity[:, None]
    out = np.where(hit.ravel()[:, None], out, 0.0)
    return np.clip(np.rint(out), 0, 255).astype(np.uint8).reshape(values.shape + (3,))


@contextlib.contextmanager
def abort_on_error(comm=None):
    """Collective work inside this block: an exception on one rank ends every rank, with its message.

    Without it a rank that fails leaves the others waiting in the next
    reduction for ever; here the failing rank prints the traceback, names
    itself and calls ``MPI_Abort``, which ends the whole job.

    Examples
    --------
    >>> with abort_on_error(world_communicator()):
    ...     pass
    """
    comm = world_communicator() if comm is None else comm
    try:
        yield
    except BaseException as error:  # noqa: BLE001  (SystemExit too: the others would hang)
        if isinstance(error, SystemExit) and not error.code:
            raise
        traceback.print_exc()
        sys.stderr.write(f"mipcast.distributed: rank {comm.rank} of {comm.size} failed ({error!r}); "
                         "aborting the job\n")
        sys.stderr.flush()
        comm.Abort(1)

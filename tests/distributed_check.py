"""Exact distributed MIP under MPI: run with ``mpiexec -n N pvbatch --symmetric tests/distributed_check.py``.

Every rank builds the same 64^3 vessel phantom (``--size``), takes its brick
(:func:`mipcast.distributed.split_extents` along ``--axis`` x, y, z or
``d3``), and renders each method through
:class:`mipcast.distributed.DistributedView`; rank 0 also renders the whole
volume in one process (:class:`mipcast.offscreen.OffscreenView`, the same
camera and window) and compares: pictures (pixels within 1 grey level) and
float images (largest difference as a fraction of the range, and the
fraction of bit-identical pixels). Rank 0 writes the results as JSON to
``--out``. ``--die-rank R`` makes rank R kill itself (SIGKILL) after the
first frame, ``--raise-rank R`` makes it raise: the job must end, not hang.

Methods on the ``"demip"`` route (``demip``, ``demip_two_pass``) run one
case per depth mode of ``--demip-modes`` and sphere weight of
``--spheres`` (one view per axis, its parameters changed between cases):
pictures (within 1 and 2 grey), the maximum's float image, the depth
against the single process's ``render_depth`` and against the float64
reference (``render_demip(output="depth")``), and whether the same pixels
get a DEMIP term.
``--max-voxels`` is each rank's texture budget (refused above it). ``--air``: the phantom as int16 HU, its
low-x half air (:func:`with_air`: split along x, the first piece one value). ``--turned ANGLE`` draws
``edge_on_check.turned``'s volume instead (a direction matrix, anisotropic spacing; with
``--view front`` its side faces seen edge-on) and compares the floats with the float64 reference too.

    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \\
    PYTHONPATH=$(python tests/installed.py) xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
    mpiexec --oversubscribe -n 2 pvbatch --symmetric tests/distributed_check.py --out /tmp/d.json
"""
import argparse
import json
import os
import signal
import time

import numpy as np

from mipcast.data_fixtures import make_fixture
from mipcast.distributed import (DistributedView, OneRank, abort_on_error, colour, extract_piece, split_extents,
                                 world_communicator)
from mipcast import methods
from mipcast.core.parameters import set_parameters
from mipcast.distributed import demip_picture
from mipcast.mappers.demip import render_depth
from mipcast.offscreen import OffscreenView
from mipcast.reference.demip import render_demip
from mipcast.core.clipping import slab_planes
from mipcast.mappers.clip_uniforms import slab_of
from mipcast.mappers.brick_rays import box_in_view
from vtkmodules.vtkRenderingCore import vtkCamera

AXES = {"x": 0, "y": 1, "z": 2, "d3": None}


def from_the_cap_error(image, view, method, values, span):
    """Against the float64 reference on the rays from VTK's near-plane cap (the camera inside): the largest float
    difference (a fraction of the range) and whether the same rays hit.  The one process's own floats are off
    by more there (VTK's ray direction from a cap point 0.2 from the eye, in float)."""
    from cap_reference import from_the_cap
    from mipcast.reference import mip as kernels

    if methods.METHODS[method].walks_cells:
        expected = from_the_cap(image, view.camera, tuple(view.local.size), kernels.exact_maximum)
    else:
        expected = from_the_cap(image, view.camera, tuple(view.local.size), kernels.sampled_maximum,
                                view.sample_distance)
    both = np.isfinite(values) & np.isfinite(expected)
    return {"cap_misses_agree": float(np.mean(np.isnan(values) == np.isnan(expected))),
            "cap_float_max_error": float(np.abs(values[both] - expected[both]).max() / span) if both.any() else 0.0}


def move_inside(camera, image):
    """``--axes x+inside``: the camera inside the volume, perspective, its near plane cutting the box (VTK then
    starts the rays at its near-plane cap); the clipping range set, the same on every rank."""
    centre = np.array(image.GetCenter())
    camera.SetParallelProjection(False)
    camera.SetViewAngle(60.0)
    camera.SetFocalPoint(*centre)
    camera.SetPosition(*(centre + [29.5, 6.5, 4.5]))
    camera.SetClippingRange(0.1, 200.1)


def moved(image):
    """``--axes y+moved``: the view's volume placed by its own matrix (turned about the volume's centre, scaled
    unevenly, shifted; still in view): the same on every rank, the single process's and the one rank's volume too."""
    from vtkmodules.vtkCommonTransforms import vtkTransform

    centre = np.array(image.GetCenter())
    transform = vtkTransform()
    transform.PostMultiply()
    transform.Translate(*(-centre))
    transform.Scale(1.0, 1.15, 0.85)
    transform.RotateX(15.0)
    transform.RotateY(-25.0)
    transform.RotateZ(10.0)
    transform.Translate(*(centre + [3.0, -2.0, 1.5]))
    return transform.GetMatrix()


def moved_error(image, view, method, values, span):
    """``+moved``: against the float64 reference of the volume placed by its matrix (samples in the volume's own
    units, as VTK's): the largest float difference (a fraction of the range) and whether the same rays hit.  The
    one process's own floats are off by more on a knife-edge pixel now and then (measured: one of 9216, 4.8e-4)."""
    entry = methods.METHODS[method]
    expected = entry.reference(image, view.camera, tuple(view.local.size), sample_distance=view.sample_distance,
                               matrix=view.local.volume.GetMatrix())
    both = np.isfinite(values) & np.isfinite(expected)
    return {"reference_misses_agree": float(np.mean(np.isnan(values) == np.isnan(expected))),
            "reference_float_max_error": float(np.abs(values[both] - expected[both]).max() / span)
            if both.any() else 0.0}


def matrix_of(view):
    """The user matrix of a DistributedView's volume (None: none), for the views it is compared with."""
    return view.local.volume.GetUserMatrix()


def compare(distributed_rgb, single_rgb, distributed_float, single_float, span):
    close = np.abs(distributed_rgb.astype(int) - single_rgb.astype(int)).max(axis=2) <= 1
    both = ~np.isnan(single_float) & ~np.isnan(distributed_float)
    miss_agree = float(np.mean(np.isnan(single_float) == np.isnan(distributed_float)))
    diff = np.abs(distributed_float[both].astype(np.float64) - single_float[both].astype(np.float64))
    return {
        "within_1_grey": float(close.mean()),
        "within_2_grey": float((np.abs(distributed_rgb.astype(int) - single_rgb.astype(int)).max(axis=2) <= 2).mean()),
        "max_grey_off": int(np.abs(distributed_rgb.astype(int) - single_rgb.astype(int)).max()),
        "float_max_error": float(diff.max() / span) if diff.size else 0.0,
        "float_identical": float((diff == 0).mean()) if diff.size else 1.0,
        "misses_agree": miss_agree,
        "lit": float((single_rgb.max(axis=2) > 8).mean()),
    }


_ONE_RANK = {}  # method -> rank 0's view of the whole volume as one rank's brick (DistributedView, OneRank)


def one_rank(method, image, args, window, view):
    """Rank 0's 1-rank DistributedView of the whole volume (the same camera): what N ranks must equal."""
    single = _ONE_RANK.get(method)
    if single is None:
        single = _ONE_RANK[method] = DistributedView(image, method, size=tuple(args.image), window=window,
                                                     comm=OneRank())
    single.camera.DeepCopy(view.camera)
    single.local.volume.SetUserMatrix(matrix_of(view))
    return single


def against_one_rank(rgb, values, one_rgb, one_values, span, depth=None, one_depth=None):
    """N ranks against 1 rank: largest grey and float difference, bit-identical floats, depth."""
    both = ~np.isnan(values) & ~np.isnan(one_values)
    diff = np.abs(values[both].astype(np.float64) - one_values[both].astype(np.float64))
    grey = np.abs(rgb.astype(int) - one_rgb.astype(int)).max(axis=2)
    out = {"one_rank_max_grey_off": int(grey.max()), "one_rank_within_1_grey": float((grey <= 1).mean()),
           "one_rank_float_max_error": float(diff.max() / span) if diff.size else 0.0,
           "one_rank_float_identical": float((diff == 0).mean()) if diff.size else 1.0,
           "one_rank_misses_agree": float(np.mean(np.isnan(values) == np.isnan(one_values)))}
    if depth is not None:
        known = ~np.isnan(depth) & ~np.isnan(one_depth)
        out["one_rank_depth_max_error"] = float(np.abs(depth[known] - one_depth[known]).max()) if known.any() else 0.0
        out["one_rank_term_agree"] = float(np.mean(np.isnan(depth) == np.isnan(one_depth)))
    return out


def _wins(comm, view, values):
    """Which rank's brick holds each pixel's maximum (pixel counts per rank): every brick must contribute."""
    wins = np.zeros(comm.size, dtype=np.int64)
    wins[comm.rank] = int(np.sum(view.last_local == values))
    if comm.size > 1:
        from mpi4py import MPI

        comm.Allreduce(MPI.IN_PLACE, wins, op=MPI.SUM)
    return wins


def save_png(args, name, rgb, values):
    from vtk_png import write_png

    os.makedirs(args.png, exist_ok=True)
    write_png(os.path.join(args.png, f"{name}.png"), rgb)
    np.save(os.path.join(args.png, f"{name}.npy"), values)


_SINGLE = {}     # method -> rank 0's one-process view (its parameters changed per case)
_REFERENCE = {}  # settings -> float64 reference depth


def demip_cases(args, comm, image, window, span, axis, axis_number, extents, method, view, settings, keep,
                results):
    """The depth mode x sphere weight cases of a ``"demip"``-route method on this split (collective)."""
    modes = args.demip_modes.split(",")
    spheres = [float(v) for v in args.spheres.split(",")]
    if method in args.sweep.split(","):
        cases = [(mode, sphere) for mode in modes for sphere in spheres]
    else:
        cases = [(modes[axis_number % len(modes)], spheres[axis_number % len(spheres)])]
    for mode, sphere in cases:
        case_settings = dict({"projection": "mip"}, **settings, depth_mode=mode, sphere_weight=sphere)
        view.set_parameters(**case_settings)
        values, depth, straight = view.demip_image()
        wins = _wins(comm, view, values)
        rgb = demip_picture(values, straight, view.local.volume.GetProperty())
        if comm.rank != 0:
            continue
        single = _SINGLE.get(method)
        if single is None:
            single = _SINGLE[method] = OffscreenView(image, method, size=tuple(args.image), window=window)
            keep.append(single)
        set_parameters(single.mapper, **case_settings)
        single.camera.DeepCopy(view.camera)
        single.volume.SetUserMatrix(matrix_of(view))
        single_float = single.float_image()
        single_rgb = single.screenshot()
        single_depth = render_depth(single.render_window, single.mapper)
        key = json.dumps(dict(case_settings, moved=matrix_of(view) is not None), sort_keys=True)
        if key not in _REFERENCE:
            extra = {}
            if case_settings.get("slab_thickness", 0.0) > 0:  # the slab's planes, and depth inside it
                slab = slab_of(view.depth_mapper, view.camera)
                extra = {"slab": slab, "clip_planes": slab_planes(*slab)}
            _REFERENCE[key] = render_demip(image, view.camera, tuple(args.image),
                                           sample_distance=view.sample_distance, window=window,
                                           output="depth", matrix=view.local.volume.GetMatrix(),
                                           **case_settings, **extra)
        reference = _REFERENCE[key]
        moved_value = {}
        if matrix_of(view) is not None:  # the maximum against float64 too (one process: 4.8e-4 off on one pixel)
            key = json.dumps({"value": case_settings.get("slab_thickness", 0.0), "moved": True})
            if key not in _REFERENCE:
                _REFERENCE[key] = render_demip(image, view.camera, tuple(args.image),
                                               sample_distance=view.sample_distance, window=window, output="value",
                                               matrix=view.local.volume.GetMatrix(), **case_settings)
            known = np.isfinite(values) & np.isfinite(_REFERENCE[key])
            moved_value = {"reference_misses_agree": float(np.mean(np.isnan(values) == np.isnan(_REFERENCE[key]))),
                           "reference_float_max_error": float(np.abs(values[known] - _REFERENCE[key][known]).max()
                                                              / span) if known.any() else 0.0}
        one = one_rank(method, image, args, window, view)
        one.set_parameters(**case_settings)
        one_values, one_depth, one_straight = one.demip_image()
        one_rgb = demip_picture(one_values, one_straight, one.local.volume.GetProperty())
        both = ~np.isnan(depth) & ~np.isnan(single_depth)
        near = ~np.isnan(depth) & ~np.isnan(reference)
        case = {"axis": axis, "method": method, "depth_mode": mode, "sphere_weight": sphere,
                "bricks": [list(e) for e in extents], "pixels_won": wins.tolist(),
                **compare(rgb, single_rgb, values.astype(np.float32), single_float, span),
                "depth_max_error": float(np.abs(depth[both] - single_depth[both]).max()) if both.any() else 0.0,
                "depth_within_1e-5": float((np.abs(depth[both] - single_depth[both]) <= 1e-5).mean())
                if both.any() else 1.0,
                "reference_depth_within_1e-5": float((np.abs(depth[near] - reference[near]) <= 1e-5).mean())
                if near.any() else 1.0,
                "reference_depth_error": float(np.abs(depth[near] - reference[near]).max()) if near.any() else 0.0,
                "term_agree": float(np.mean(np.isnan(depth) == np.isnan(single_depth))),
                **against_one_rank(rgb, values, one_rgb, one_values, span, depth, one_depth), **moved_value,
                "reference_term_agree": float(np.mean(np.isnan(depth) == np.isnan(reference)))}
        results["cases"].append(case)
        print(json.dumps(case), flush=True) if os.environ.get("MIPCAST_CHECK_VERBOSE") else None
        if args.png:
            save_png(args, f"{method}-{mode}-s{sphere:g}-{axis}-n{comm.size}", rgb, values)
            save_png(args, f"{method}-{mode}-s{sphere:g}-single", single_rgb, single_float)


def ordered_cases(args, comm, image, window, span, axis, extents, method, view, settings, keep, results):
    """DEMIP's ordered projections (``--projections``) on this split, turn by turn over the ranks (collective).

    One case per projection with ``settings`` (the first depth mode and sphere weight) and, where
    ``settings`` has a slab, one without it: the picture against the single process's and (MIDA) the
    float64 reference's composite; LMIP's and attenuated MIP's value and LMIP's depth against the single
    process's readouts and the float64 reference, and against the whole volume as one rank's brick.
    """
    variants = [(dict(settings), False)]
    if settings.get("slab_thickness", 0.0) > 0:
        variants.append((dict(settings, slab_thickness=0.0), False))
    ordered = [p for p in args.projections.split(",") if p and p != "mip"]
    cases = [(projection, variant, False) for projection in ordered for variant, _ in variants]
    if args.zoomed and ordered and AXES[axis.partition("+")[0]] is not None:
        cases.append((ordered[0], variants[-1][0], True))
    saved = vtkCamera()
    saved.DeepCopy(view.camera)
    for projection, variant, zoomed in cases:
        view.camera.DeepCopy(saved)
        if zoomed:  # a parallel view of the high end of the split axis: the first bricks are out of view
            bounds = image.GetBounds()
            split = AXES[axis.partition("+")[0]]
            across = (split + 1) % 3
            focal = [0.5 * (bounds[2 * a] + bounds[2 * a + 1]) for a in range(3)]
            focal[split] = bounds[2 * split + 1] - 4.0
            position = list(focal)
            position[across] += 200.0
            up = [0.0, 0.0, 0.0]
            up[3 - split - across] = 1.0
            view.camera.SetFocalPoint(focal)
            view.camera.SetPosition(position)
            view.camera.SetViewUp(up)
            view.camera.SetParallelProjection(True)
            view.camera.SetParallelScale(12.0)
            view.camera.SetClippingRange(1.0, 1000.0)
        case_settings = dict(variant, projection=projection, depth_mode=args.demip_modes.split(",")[0],
                             sphere_weight=float(args.spheres.split(",")[0]))
        if args.fail_turn_rank == comm.rank:
            from mipcast.mappers import rank_ordered

            def failing(*_, **__):
                raise RuntimeError("rank asked to fail in its turn (--fail-turn-rank)")

            rank_ordered._draw_turn = failing
        view.set_parameters(**case_settings)
        started = time.perf_counter()
        values, depth, _ = view.demip_image()
        seconds = time.perf_counter() - started
        in_view = np.zeros(comm.size)
        in_view[comm.rank] = float(box_in_view(view.ordered_volume, view.local.renderer, values.shape))
        if comm.size > 1:
            from mpi4py import MPI

            comm.Allreduce(MPI.IN_PLACE, in_view, op=MPI.SUM)
        rgb = np.clip(np.rint(view.last_rgba[..., :3] * 255.0), 0, 255).astype(np.uint8)
        if comm.rank != 0:
            continue
        single = _SINGLE.get(method)
        if single is None:
            single = _SINGLE[method] = OffscreenView(image, method, size=tuple(args.image), window=window)
            keep.append(single)
        set_parameters(single.mapper, **case_settings)
        single.camera.DeepCopy(view.camera)
        single.volume.SetUserMatrix(matrix_of(view))
        single_rgb = single.screenshot()
        extra = {}
        if case_settings.get("slab_thickness", 0.0) > 0:
            slab = slab_of(view.depth_mapper, view.camera)
            extra = {"slab": slab, "clip_planes": slab_planes(*slab)}

        def reference(output):
            return render_demip(image, view.camera, tuple(args.image), sample_distance=view.sample_distance,
                                window=window, output=output, matrix=view.local.volume.GetMatrix(),
                                **case_settings, **extra)

        grey = np.abs(rgb.astype(int) - single_rgb.astype(int)).max(axis=2)
        case = {"axis": axis, "method": method, "projection": projection, "zoomed": zoomed,
                "bricks_in_view": in_view.tolist(),
                "slab_thickness": case_settings.get("slab_thickness", 0.0),
                "depth_mode": case_settings["depth_mode"], "bricks": [list(e) for e in extents],
                "seconds": seconds, "within_1_grey": float((grey <= 1).mean()), "max_grey_off": int(grey.max()),
                "lit": float((single_rgb.max(axis=2) > 8).mean())}
        if projection == "mida":
            composite = np.rint(255.0 * reference("rgb"))
            hit = np.isfinite(composite).all(axis=-1)
            case["reference_hits"] = float(hit.mean())
            case["reference_within_1_grey"] = float(
                (np.abs(rgb[hit].astype(int) - composite[hit]).max(axis=-1) <= 1).mean()) if hit.any() else 0.0
        else:
            single_float = single.float_image()
            single_depth = render_depth(single.render_window, single.mapper)
            expected, expected_depth = reference("value"), reference("depth")
            one = one_rank(method, image, args, window, view)
            one.set_parameters(**case_settings)
            one_values, one_depth, _ = one.demip_image()
            for name, other in (("", single_float), ("reference_", expected), ("one_rank_", one_values)):
                both = np.isfinite(values) & np.isfinite(other)
                diff = np.abs(values[both] - other[both])
                case[name + "misses_agree"] = float(np.mean(np.isnan(values) == np.isnan(other)))
                case[name + "float_max_error"] = float(diff.max() / span) if diff.size else 0.0
            for name, other in (("", single_depth), ("reference_", expected_depth), ("one_rank_", one_depth)):
                both = np.isfinite(depth) & np.isfinite(other)
                case[name + "term_agree"] = float(np.mean(np.isnan(depth) == np.isnan(other)))
                case[name + "depth_within_1e-5"] = float((np.abs(depth[both] - other[both]) <= 1e-5).mean()) \
                    if both.any() else 1.0
            case["depth_terms"] = float(np.isfinite(depth).mean())
            mip = render_demip(image, view.camera, tuple(args.image),
                                               sample_distance=view.sample_distance, window=window,
                                               output="value", matrix=view.local.volume.GetMatrix(),
                                               **dict(case_settings, projection="mip"), **extra)
            known = np.isfinite(values) & np.isfinite(mip)
            case["differs_from_mip"] = float((np.abs(values[known] - mip[known]) > 1e-3 * span).mean()) \
                if known.any() else 0.0
        results["cases"].append(case)
        print(json.dumps(case), flush=True) if os.environ.get("MIPCAST_CHECK_VERBOSE") else None
        if args.png:
            tag = f"{method}-{projection}-slab{case['slab_thickness']:g}{'-zoomed' if zoomed else ''}"
            save_png(args, f"{tag}-{axis}-n{comm.size}", rgb, values)
            save_png(args, f"{tag}-single", single_rgb, values)
    view.camera.DeepCopy(saved)


def with_missing(image, kind="scattered"):
    """``image`` with missing (NaN) voxels.  ``"scattered"``: a square tube along x (through every brick of an x
    split), the low-y quarter of the high-x half (rays along x meet finite data in one brick and only missing data
    in the other) and its high-z quarter of the low-x half; the values in the high-x half raised by half the range,
    so the bricks' own finite ranges differ.  ``"brick"``: the low-x half and two more columns missing (split
    along x, the first brick holds missing values only)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float32).reshape(nz, ny, nx).copy()
    if kind == "brick":
        values[:, :, : nx // 2 + 2] = np.nan
    else:
        values[:, :, nx // 2:] += 0.5
        values[nz // 3: nz // 2, ny // 3: ny // 2, :] = np.nan
        values[:, : ny // 4, nx // 2:] = np.nan
        values[3 * nz // 4:, :, : nx // 2] = np.nan
    return _with_values(image, values, "values")


def with_air(image):
    """``image`` as a CT holds it: int16 (the phantom's 0..1 as -1000..1000 HU), its low-x half and two more
    columns air (-1000): split along x, the first piece holds one value."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float64).reshape(nz, ny, nx)
    low, high = values.min(), values.max()
    hu = np.rint(-1000.0 + 2000.0 * (values - low) / (high - low)).astype(np.int16)
    hu[:, :, : nx // 2 + 2] = -1000
    return _with_values(image, hu, "HU")


def _with_values(image, values, name: str):
    """A new image of ``image``'s structure holding ``values`` (z, y, x) as its point scalars ``name``."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData

    out = vtkImageData()
    out.CopyStructure(image)
    array = numpy_to_vtk(values.ravel(), deep=True)
    array.SetName(name)
    out.GetPointData().SetScalars(array)
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", required=True)
    parser.add_argument("--size", type=int, default=64)
    parser.add_argument("--image", type=int, nargs=2, default=(96, 96))
    parser.add_argument("--axes", default="x,y,z,d3",
                        help="the splits; 'x+inside': along x, the camera inside the volume (move_inside); "
                             "'y+moved': along y, the volume placed by its own matrix (moved)")
    parser.add_argument("--methods", default="mip,analytic")
    parser.add_argument("--view", default="oblique", help="the view preset (mipcast.offscreen.VIEWS)")
    parser.add_argument("--turned", type=float, default=None, metavar="ANGLE",
                        help="edge_on_check.turned's volume (the vessels on anisotropic spacing, turned ANGLE rad "
                             "about z by its direction matrix) in place of the phantom; floats against the float64 "
                             "reference too (with --view front its side faces are seen edge-on)")
    parser.add_argument("--set", action="append", default=[], metavar="METHOD:NAME=VALUE",
                        help="a parameter for one method, e.g. analytic:packed_corners=0")
    parser.add_argument("--demip-modes", default="window,steps,entry_plus_length,eye_distance")
    parser.add_argument("--spheres", default="0,0.5", help="sphere weights of the DEMIP cases")
    parser.add_argument("--sweep", default="demip",
                        help="'demip'-route methods that run every mode x sphere on every split; the others "
                             "run one case per split (split j: mode j, sphere j, cycling)")
    parser.add_argument("--projections", default="mip",
                        help="DEMIP projections: 'mip' (the depth mode x sphere cases) and / or the ordered ones "
                             "(lmip, attenuated, mida: one case per split, with and without the slab)")
    parser.add_argument("--zoomed", action="store_true",
                        help="one more ordered case: a parallel view of the split axis's high end (bricks out of view)")
    parser.add_argument("--fail-turn-rank", type=int, default=None,
                        help="this rank raises in its ordered turn: every rank must end with a message")
    parser.add_argument("--ghost", type=int, default=0)
    parser.add_argument("--max-voxels", type=int, default=None)
    parser.add_argument("--die-rank", type=int, default=None)
    parser.add_argument("--raise-rank", type=int, default=None)
    parser.add_argument("--png", default=None, help="folder for rank 0's PNGs (distributed, single)")
    parser.add_argument("--missing", choices=("scattered", "brick"), default=None,
                        help="the phantom with missing (NaN) voxels: with_missing")
    parser.add_argument("--air", action="store_true",
                        help="the phantom as int16 HU with its low-x half air: with_air")
    args = parser.parse_args(argv)
    comm = world_communicator()
    if args.turned is None:
        image = make_fixture("vessels", size=args.size)
    else:
        from edge_on_check import turned
        image = turned(args.size, args.turned)
    image = with_missing(image, args.missing) if args.missing else image
    image = with_air(image) if args.air else image
    span = float(np.subtract(*image.GetPointData().GetScalars().GetFiniteRange()[::-1]))
    window = image.GetPointData().GetScalars().GetFiniteRange()
    results = {"ranks": comm.size, "cases": []}
    keep = []  # every window stays open to the end: closing one X display and opening the next aborts now and then
    with abort_on_error(comm):
        frame = 0
        for axis_number, axis in enumerate(args.axes.split(",")):
            split, _, flag = axis.partition("+")
            extents = split_extents(image.GetExtent(), comm.size, AXES[split], ghost=args.ghost)
            brick = extract_piece(image, extents[comm.rank])
            for method in args.methods.split(","):
                settings = {}
                for item in args.set:
                    owner, pair = item.split(":", 1)
                    name, value = pair.split("=", 1)
                    if owner == method:
                        settings[name] = json.loads(value)
                view = DistributedView(brick, method, size=tuple(args.image), window=window, comm=comm,
                                       max_voxels=args.max_voxels, view=args.view, **settings)
                if flag == "inside":
                    move_inside(view.camera, image)
                elif flag == "moved":
                    view.local.volume.SetUserMatrix(moved(image))
                keep.append(view)
                if methods.METHODS[method].distributed == "demip":
                    frame += 1
                    if args.raise_rank == comm.rank and frame == 1:
                        raise RuntimeError("rank asked to fail (--raise-rank)")
                    if "mip" in args.projections.split(","):
                        demip_cases(args, comm, image, window, span, axis, axis_number, extents, method, view,
                                    settings, keep, results)
                    ordered_cases(args, comm, image, window, span, axis, extents, method, view, settings, keep,
                                  results)
                    continue
                values = view.float_image()
                wins = _wins(comm, view, values)
                rgb = colour(values, view.local.volume.GetProperty())
                frame += 1
                if args.die_rank == comm.rank and frame == 1:
                    os.kill(os.getpid(), signal.SIGKILL)
                if args.raise_rank == comm.rank and frame == 1:
                    raise RuntimeError("rank asked to fail (--raise-rank)")
                if comm.rank == 0:
                    single = OffscreenView(image, method, size=tuple(args.image), window=window)
                    keep.append(single)
                    if settings:
                        set_parameters(single.mapper, **settings)
                    single.camera.DeepCopy(view.camera)
                    single.volume.SetUserMatrix(matrix_of(view))
                    single_float = single.float_image()
                    single_rgb = single.screenshot()
                    one = one_rank(method, image, args, window, view)
                    if settings:
                        one.set_parameters(**settings)
                    one_values = one.float_image()
                    case = {"axis": axis, "method": method, "bricks": [list(e) for e in extents],
                            "pixels_won": wins.tolist(), "seconds": view.last_times,
                            **compare(rgb, single_rgb, values, single_float, span),
                            **against_one_rank(rgb, values, colour(one_values, one.local.volume.GetProperty()),
                                               one_values, span)}
                    if flag == "inside":  # the float64 samples / walk from VTK's near-plane cap
                        case.update(from_the_cap_error(image, view, method, values, span))
                    elif flag == "moved" or args.turned is not None:  # the float64 reference (of the volume where its matrix puts it)
                        case.update(moved_error(image, view, method, values, span))
                    results["cases"].append(case)
                    print(json.dumps(case), flush=True) if os.environ.get("MIPCAST_CHECK_VERBOSE") else None
                    if args.png:
                        save_png(args, f"{method}-{axis}-n{comm.size}", rgb, values)
                        save_png(args, f"{method}-single", single_rgb, single_float)
    if comm.rank == 0:
        with open(args.out, "w") as handle:
            json.dump(results, handle, indent=1)
    return 0


if __name__ == "__main__":
    main()  # no sys.exit: pvbatch must finalize MPI on every rank

"""The foveated method's reduction over ranks (mipcast.mappers.rank_foveated) in one process, without MPI.

Several ranks are simulated in one process (and one rank without data): each "rank" composes with its own piece, and its
reductions combine its arrays with those the other ranks passed at the same collective (rounds
until every collective has seen the others' final inputs: 4 collectives, 4 rounds).  The composed
picture must match the one-texture GPU foveated picture of the whole volume: every pixel within 1 grey
(the CPU blend mirrors the GPU's arithmetic; on Mesa llvmpipe it is equal, bit for bit).
"""
import numpy as np
import pytest

from mipcast.core.object_state import object_state
from mipcast.mappers import rank_foveated
from vtkmodules.vtkImagingCore import vtkExtractVOI
from test_bricked_mapper import DISTANCE, image, picture, pipeline  # noqa: F401  (fixture)

_COMBINE = {"max": np.maximum, "min": np.minimum, "sum": np.add}


def simulate(mapper, renderer, pieces, stub, rounds=4):
    """Every piece's compose, its reductions combining all pieces' arrays of the same call."""
    records = [[] for _ in pieces]
    results = [None] * len(pieces)

    for _ in range(rounds):
        for rank, piece in enumerate(pieces):
            calls = []

            def reduce(array, op, rank=rank, calls=calls):
                index = len(calls)
                calls.append(np.asarray(array, dtype=np.float64).copy())
                out = calls[-1]
                for other, record in enumerate(records):
                    if other != rank and index < len(record) and record[index].shape == out.shape:
                        out = _COMBINE[op](out, record[index])
                return out

            def start(caller, event, piece=piece, reduce=reduce, rank=rank):
                if piece is None:  # a rank without data: no mapper, no piece, no whole extent; it takes part
                    results[rank] = rank_foveated.compose(None, None, caller, None, None, reduce)
                else:
                    results[rank] = rank_foveated.compose(mapper, mapper.GetAttachedVolume(), caller, piece, stub,
                                                          reduce)

            tag = renderer.AddObserver("StartEvent", start)
            renderer.GetRenderWindow().Render()
            renderer.RemoveObserver(tag)
            records[rank] = calls
    return results


def _stub(image):
    direction = image.GetDirectionMatrix()
    return (tuple(image.GetExtent()), image.GetOrigin(), image.GetSpacing(),
            [direction.GetElement(i, j) for i in range(3) for j in range(3)])


def _projected_box(renderer, bounds, shape):
    """Which pixels (top row first) the screen rectangle of the projected corners of ``bounds`` covers."""
    xs, ys = [], []
    for x in bounds[0:2]:
        for y in bounds[2:4]:
            for z in bounds[4:6]:
                renderer.SetWorldPoint(x, y, z, 1.0)
                renderer.WorldToDisplay()
                point = renderer.GetDisplayPoint()
                xs.append(point[0])
                ys.append(point[1])
    rows, columns = np.arange(shape[0])[::-1, None] + 0.5, np.arange(shape[1])[None, :] + 0.5
    return (columns >= min(xs)) & (columns <= max(xs)) & (rows >= min(ys)) & (rows <= max(ys))


def _grey(rgba):
    return np.clip(rgba[..., :3] * 255.0 + 0.5, 0.0, 255.0).astype(int)


def _pieces(image, axis, count):
    extent = list(image.GetExtent())
    cuts = [round(extent[2 * axis + 1] * k / count) for k in range(count + 1)]
    pieces = []
    for k in range(count):  # pieces sharing a layer of points, as ParaView's
        e = list(extent)
        e[2 * axis], e[2 * axis + 1] = cuts[k], cuts[k + 1]
        voi = vtkExtractVOI()
        voi.SetInputData(image)
        voi.SetVOI(*e)
        voi.Update()
        pieces.append(voi.GetOutput())
    return pieces


@pytest.mark.parametrize("layer, axis, count", [("mip", 0, 2), ("analytic", 2, 3)])
def test_pieces_reduced_draw_the_one_texture_foveated_picture(image, layer, axis, count):
    mapper, renderer, window = pipeline(image, "foveated")
    mapper.SetMethod(layer)
    mapper.SetGazePoint(0.3, 0.6)
    renderer.SetBackground(0.0, 0.0, 0.0)
    one = picture(window)
    results = simulate(mapper, renderer, _pieces(image, axis, count) + [None], _stub(image))
    assert results[-1] == (None, None)  # the rank without data took part and draws nothing
    results = results[:-1]
    for rgba, problem in results:
        assert problem is None and rgba is not None
    final = [_grey(rgba) for rgba, _ in results]
    for other in final[1:]:
        assert np.array_equal(other, final[0])  # every rank the same picture
    assert (one.max(axis=-1) > 10).mean() > 0.2
    difference = np.abs(final[0] - one).max(axis=-1)
    share, exact = (difference <= 1).mean(), (difference == 0).mean()
    plan, values, volume_levels = object_state(mapper)["rank_foveated_values"]
    assert len(plan.layers) == 3 and max(volume_levels) > 0  # coarse pyramid levels reduced over the pieces
    print(f"{layer} {count} pieces along {'xyz'[axis]}, volume levels {volume_levels}: "
          f"{100 * share:.2f} % within 1 grey ({100 * exact:.2f} % equal), max {difference.max()}")
    # the CPU blend mirrors the GPU's arithmetic (VTK's transfer-function textures, the 8-bit image-sample
    # framebuffer, 8-bit filtering and blending): every pixel within 1 grey (llvmpipe: equal)
    assert difference.max() <= 1, (difference.max(), (difference > 1).sum())
    # the spill: lit pixels beyond the whole volume's projected box, inside the spill prop's (IceT's box)
    lit = results[0][0][..., 3] > 0
    inside_box = _projected_box(renderer, image.GetBounds(), lit.shape)
    inside_spill = _projected_box(renderer, object_state(mapper)["rank_foveated_bounds"], lit.shape)
    print(f"  {(lit & ~inside_box).sum()} lit pixels beyond the volume's projected box, "
          f"{(lit & ~inside_spill).sum()} beyond the spill bounds'")
    assert (lit & ~inside_box).any() and not (lit & ~inside_spill).any()
    # the reduced full-resolution level against the float64 reference of the whole volume, where it cast
    from mipcast.methods import METHODS

    reference = METHODS[layer].reference(image, renderer.GetActiveCamera(), window.GetSize(),
                                       sample_distance=DISTANCE)
    level0 = values[0]
    cast = np.isfinite(level0) & np.isfinite(reference)
    low, high = image.GetPointData().GetScalars().GetRange(0)
    assert cast.mean() > 0.05
    error = np.abs(level0[cast] - reference[cast]).max() / (high - low)
    print(f"  level 0 vs the float64 reference: {cast.sum()} rays, max error {error:.2e} of the range")
    assert error <= METHODS[layer].reference_tolerance


def _with_missing(image):
    """``image`` with missing (NaN) voxels: a block crossing the pieces' borders, a slab along the low-x side (rays
    through missing data only, coarse points of missing voxels only) and finite corners beyond the range."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData

    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float32).copy()
    block = values.reshape(image.GetDimensions()[::-1])
    block[8:40, 10:38, 20:28] = np.nan
    block[:, :, :3] = np.nan
    values[0], values[-1] = 2.0, -1.0
    out = vtkImageData()
    out.DeepCopy(image)
    out.GetPointData().SetScalars(numpy_to_vtk(values, deep=True))
    return out


@pytest.mark.parametrize("layer, missing, tolerance", [("demip", False, 0.0), ("demip", True, 0.0),
                                                       ("mip", False, 4.0), ("mip", True, 0.0), ("analytic", True, 0.0)])
def test_demip_layers_missing_values_and_content_adaptive_density_reduce_exactly(image, layer, missing, tolerance):
    """DEMIP levels (phase 1 MAX, phase 2 MIN, the colours on the CPU from the level's GPU tables), missing values
    (the whole fill, coarse points of missing voxels only) and content-adaptive masks from the reduced coarsest
    level over 2 pieces: the one-texture picture, every pixel within 1 grey.  Measured before the missing voxels'
    sentinel was float64 (in float32 it became -inf: "no rank covered", the lowest value): ``mip`` with missing
    values, 53 pixels up to 32 off.  (The DEMIP colours from the functions, not the level's GPU tables: max 1 here,
    12 pixels 2 off in ParaView, tests/test_representation_distributed.py.)"""
    image = _with_missing(image) if missing else image
    mapper, renderer, window = pipeline(image, "foveated")
    mapper.SetMethod(layer)
    mapper.SetGazePoint(0.3, 0.6)
    mapper.SetContentTolerance(tolerance)
    renderer.SetBackground(0.0, 0.0, 0.0)
    one = picture(window)
    results = simulate(mapper, renderer, _pieces(image, 0, 2) + [None], _stub(image))
    assert results[-1] == (None, None)
    (rgba, problem), (other, _) = results[0], results[1]
    assert problem is None and rgba is not None, problem
    assert np.array_equal(_grey(rgba), _grey(other))
    difference = np.abs(_grey(rgba) - one).max(axis=-1)
    print(f"{layer}, missing {missing}, tolerance {tolerance}: {100 * (difference <= 1).mean():.2f} % within 1 grey, "
          f"max {difference.max()}")
    assert (one.max(axis=-1) > 10).mean() > 0.2 and difference.max() <= 1, (difference.max(), (difference > 1).sum())


def _opacity_ramp(mapper, image):
    low, high = image.GetPointData().GetScalars().GetRange(0)
    opacity = mapper.GetAttachedVolume().GetProperty().GetScalarOpacity()
    opacity.RemoveAllPoints()
    opacity.AddPoint(low, 0.0)
    opacity.AddPoint(low + 0.1 * (high - low), 0.0)
    opacity.AddPoint(high, 0.8)


def _clip_plane(mapper, image):
    from vtkmodules.vtkCommonDataModel import vtkPlane

    plane = vtkPlane()
    plane.SetOrigin(*image.GetCenter())
    plane.SetNormal(0.3, 1.0, 0.2)
    mapper.AddClippingPlane(plane)


def _crop(mapper, image):
    b = image.GetBounds()
    at = [b[2 * (i // 2)] + f * (b[2 * (i // 2) + 1] - b[2 * (i // 2)]) for i, f in
          enumerate((0.2, 0.7, 0.25, 0.75, 0.2, 0.8))]
    mapper.SetCropping(True)
    mapper.SetCroppingRegionPlanes(*at)
    mapper.SetCroppingRegionFlagsToInvertedCross()


@pytest.mark.parametrize("tolerance, bound", [(0.0, 2), (4.0, 3)], ids=["acuity only", "content-adaptive"])
def test_content_adaptive_semi_transparent_rays_over_pieces_show_the_background_as_on_one_process(image, tolerance,
                                                                                                bound):
    """An opacity ramp and a coloured background: a finer level's cast ray is drawn over the background, not
    over the coarser levels beneath (shaders/foveated_paint_beneath.glsl); the ranks' blend does the same.
    Without that step in rank_foveated.blend_levels 2182 pixels are up to 210 grey off the one-process picture.
    With it up to ``bound`` grey, from the order of 8-bit rounding where a level is not opaque: the ranks blend
    the levels over transparent black and the result goes over the background afterwards (as IceT's does), the
    window blends them over the background; acuity-only foveation, which this does not touch, differs by up to
    2 grey the same way (on a black background, where both orders agree, within 1 grey: the tests above)."""
    change = _opacity_ramp
    mapper, renderer, window = pipeline(image, "foveated")
    mapper.SetGazePoint(0.5, 0.5)
    mapper.SetContentTolerance(tolerance)
    change(mapper, image)
    renderer.SetBackground(0.1, 0.2, 0.3)
    one = picture(window)
    results = simulate(mapper, renderer, _pieces(image, 0, 2), _stub(image))
    (rgba, problem), (other, _) = results
    assert problem is None and rgba is not None, problem
    assert np.array_equal(_grey(rgba), _grey(other))
    background = np.round(np.array([0.1, 0.2, 0.3]) * 255.0)
    over = _grey(rgba) + np.floor((1.0 - rgba[..., 3:4]) * background + 0.5).astype(int)  # over the background
    difference = np.abs(over - one).max(axis=-1)
    assert (np.abs(one - background).max(axis=-1) > 10).mean() > 0.05   # the vessels drawn (8.9 % of the pixels)
    assert difference.max() <= bound, (difference.max(), (difference > 1).sum())


@pytest.mark.parametrize("layer", ["mip", "analytic"])
def test_content_adaptive_specks_the_coarse_rays_missed_stay_in_the_fovea_over_pieces(layer):
    """The data's structure bound (mipcast.core.structure_bound) over 3 pieces: each rank's piece's bound, reduced
    with MAX, casts the fovea's rays at specks no coarse ray saw; the picture is the one-texture one, and its fovea
    shows every speck."""
    from mipcast.bench.stability import SPECK_WINDOW, _specks
    from mipcast.core.foveation import eccentricity
    from mipcast.offscreen import grey_property

    specks = _specks()
    mapper, renderer, window = pipeline(specks, "foveated")
    mapper.SetMethod(layer)
    mapper.SetContentTolerance(2.0)
    mapper.GetAttachedVolume().SetProperty(grey_property(SPECK_WINDOW))
    renderer.SetBackground(0.0, 0.0, 0.0)
    one = picture(window)
    results = simulate(mapper, renderer, _pieces(specks, 1, 3) + [None], _stub(specks))
    (rgba, problem) = results[0]
    assert problem is None and rgba is not None, problem
    plan, values, _ = object_state(mapper)["rank_foveated_values"]
    assert np.array_equal(_grey(rgba), _grey(results[1][0]))
    difference = np.abs(_grey(rgba) - one).max(axis=-1)
    assert difference.max() <= 1, (difference.max(), (difference > 1).sum())
    full_mapper, full_renderer, full_window = pipeline(specks, layer)
    full_mapper.GetAttachedVolume().SetProperty(grey_property(SPECK_WINDOW))
    full_renderer.SetBackground(0.0, 0.0, 0.0)
    full = picture(full_window)
    height, width = full.shape[:2]
    fovea = eccentricity((width, height), plan.gaze, width / height) <= mapper.GetFovealRadius()
    structure = fovea & (full.max(axis=-1) > 0)
    assert structure.sum() >= 10 and np.abs(_grey(rgba) - full).max(axis=-1)[structure].max() <= 1


def test_content_adaptive_density_on_missing_values_is_refused_with_the_reason(image):
    """One process paints what lies beneath a fovea ray that meets missing data only; the ranks' blend does not
    reproduce that yet, so every rank refuses (the same head) and says what to do."""
    mapper, renderer, window = pipeline(_with_missing(image), "foveated")
    mapper.SetContentTolerance(4.0)
    results = simulate(mapper, renderer, _pieces(_with_missing(image), 0, 2) + [None], _stub(image))
    assert all(rgba is None and problem == rank_foveated.MISSING_ADAPTIVE for rgba, problem in results)
    assert "content_tolerance 0" in rank_foveated.MISSING_ADAPTIVE


@pytest.mark.parametrize("gaze", [(0.1, 0.5), (0.85, 0.8)])
def test_content_adaptive_background_covers_the_coarse_levels_past_the_outline_as_on_one_process(image, gaze):
    """The volume's outline crosses the fovea, on a coloured background: the background goes over the deciding
    levels' stretch past the outline with level 0's weight (content_adaptive.outline_cover), on one process and
    in the ranks' blend.  Without it in rank_foveated.blend_levels 157-270 pixels are 44-105 grey off the
    one-process picture; with it up to 2 grey (the order of 8-bit rounding where the cover is not opaque, as in
    the opacity-ramp test above)."""
    from mipcast.core import content_adaptive

    mapper, renderer, window = pipeline(image, "foveated")
    mapper.SetGazePoint(*gaze)
    mapper.SetContentTolerance(4.0)
    renderer.SetBackground(0.1, 0.2, 0.3)
    one = picture(window)
    assert content_adaptive.outline_cover(mapper.GetLastPlan(), mapper.GetLastSilhouette()) is not None
    (rgba, problem), (other, _) = simulate(mapper, renderer, _pieces(image, 0, 2), _stub(image))
    assert problem is None and np.array_equal(_grey(rgba), _grey(other)), problem
    background = np.round(np.array([0.1, 0.2, 0.3]) * 255.0)
    over = _grey(rgba) + np.floor((1.0 - rgba[..., 3:4]) * background + 0.5).astype(int)  # over the background
    difference = np.abs(over - one).max(axis=-1)
    assert difference.max() <= 2, (difference.max(), (difference > 1).sum())


@pytest.mark.parametrize("cut", [_clip_plane, _crop], ids=["clipping", "cropping"])
def test_content_adaptive_density_with_cuts_is_refused_with_the_reason(image, cut):
    """A fovea ray cut away entirely paints what lies beneath on one process; the ranks cannot tell it from a ray
    outside the volume in their reduced values (painting inside the volume's outline left 22 pixels 2 grey off
    with a clipping plane, and drew 39 pixels up to 22 grey off without any cut; without painting, 358 pixels
    up to 43 grey off)."""
    mapper, renderer, window = pipeline(image, "foveated")
    mapper.SetContentTolerance(4.0)
    cut(mapper, image)
    for rgba, problem in simulate(mapper, renderer, _pieces(image, 0, 2), _stub(image), rounds=1):
        assert rgba is None and problem == rank_foveated.CUT_ADAPTIVE
    mapper.SetContentTolerance(0.0)   # acuity-only foveation composites with the cut
    for rgba, problem in simulate(mapper, renderer, _pieces(image, 0, 2), _stub(image), rounds=1):
        assert rgba is not None and problem is None


def test_content_adaptive_density_on_a_gradient_background_is_refused(image):
    """The masks compare the coarsest level with what lay beneath it: the ranks know only a single colour."""
    mapper, renderer, window = pipeline(image, "foveated")
    mapper.SetContentTolerance(4.0)
    renderer.GradientBackgroundOn()
    rgba, problem = simulate(mapper, renderer, [image], _stub(image), rounds=1)[0]
    assert rgba is None and "single-colour background" in problem and "use " in problem


def test_pieces_partial_pyramids_reduce_to_the_whole_pyramid():
    from mipcast.data_fixtures import make_fixture
    from mipcast.mappers.volume_pyramid import build_max_pyramid
    from vtkmodules.util.numpy_support import vtk_to_numpy

    image = make_fixture("vessels", size=21)
    dims = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(dims[::-1]).astype(np.float64)
    whole = [vtk_to_numpy(level.GetPointData().GetScalars()).reshape(level.GetDimensions()[::-1])
             for level in build_max_pyramid(image, 4)[1:]]
    cuts = {0: (0, 7, 20), 1: (0, 12, 20), 2: (0, 5, 11, 20)}
    reduced = [np.full(level.shape, -np.inf) for level in whole]
    for i in range(len(cuts[0]) - 1):
        for j in range(len(cuts[1]) - 1):
            for k in range(len(cuts[2]) - 1):
                (x0, x1), (y0, y1), (z0, z1) = ((cuts[a][n], cuts[a][n + 1]) for a, n in ((0, i), (1, j), (2, k)))
                share = rank_foveated.partial_pyramid(values[z0:z1 + 1, y0:y1 + 1, x0:x1 + 1], (x0, y0, z0), dims, 4)
                for level, ((ox, oy, oz), part) in zip(reduced, share):
                    z, y, x = part.shape
                    level[oz:oz + z, oy:oy + y, ox:ox + x] = np.maximum(level[oz:oz + z, oy:oy + y, ox:ox + x], part)
    assert len(reduced) == len(whole) == 3
    for mine, theirs in zip(reduced, whole):
        assert np.array_equal(mine, theirs)

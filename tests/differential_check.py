"""Random combinations of input and settings, every exact-readout method against its float64 reference.

    python tests/differential_check.py [--first 0] [--count 60] [--cases K ...] [--after OFFSET]

Case ``k`` (seeded by ``k``, so a failure is replayed by its number) draws the vessels 24^3 with a random
method (those with a float readout and a reference; or the foveated method, a random layer, gaze and
content tolerance, its fovea against the layer's reference: exact with acuity only, within 1 grey of the
window wherever a structure is above its floor with content-adaptive density, issue 17), scalar type
(float32, float64, int16, uint8), NaN holes, a mask (SetMaskInput, the reference given NaN there),
3-component vectors (their magnitude or one component), anisotropic spacing, a rotated direction, an
extent not from 0, a volume matrix, a sample distance, a slab, a clipping plane, cropping regions, bricks
(a texture limit of 12), view, picture size (40x36 or 41x37), grey window, cell scalars (drawn at the
cell centres), for the sampled mip, minip, average and DEMIP nearest-neighbour interpolation and, for DEMIP, its projection
(LMIP, attenuated, MIDA), thresholds, depth mode, depth weight, colour sphere and chromadepth, and prints the cases whose
float readout is off the reference by more than the method's tolerance (sampled methods on 8-bit data: 2 of 250, the
texture unit's 8-bit filtering, docs/reliability.md) or disagree on hit and miss on more than 3 % of the
pixels, or, for the methods whose picture is their value through the window's grey ramp (GREY), whose
picture is more than 2 grey off the reference's on more than 1 % of the pixels (one case in two drawn with a
random colour map and opacity, a ramp, sigmoid, step, V, band or half transparent: the reference through
those functions, over black; DEMIP too, but MIDA, on 8-bit data or with the step), or, for DEMIP (not under
nearest-neighbour interpolation), whose depth (the readout "depth") is more than 1e-4 off the reference's on
more than 1 % of the pixels or whose picture is more than 2 grey off the reference's colours on more than 1 %
(ties at the material threshold and the window's floor bounded by the references with both moved by the
value's tolerance). One case in four draws with MSAA (4 samples; the pictures then checked where the
reference draws all or nothing of a pixel's 3x3 neighbourhood).  docs/reliability.md, "Ties", lists what it
found.
"""
import argparse
import functools
import itertools
import random
import warnings
from typing import Optional

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction, vtkPlane
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty

from mipcast.core import foveation
from mipcast.core.clipping import slab_planes
from mipcast.core.object_state import object_state
from mipcast.data_fixtures import make_fixture
from mipcast import methods, reference
from mipcast.methods import METHODS
from mipcast.core.prepare import scalar_image
from mipcast.core.transfer_bounds import constant_ends
from mipcast.core.windowing import resolve_window
from mipcast.mappers.input_preparer import window_image
from mipcast.mappers.demip import DEMIPVolumeMapper, render_depth
from mipcast.offscreen import OffscreenView, set_view
from mipcast.reference import demip as reference_demip, rays

CHECKED = [name for name, method in METHODS.items() if method.float_readout and method.reference is not None]
SIZE = (40, 36)
TYPES = {"f32": np.float32, "f64": np.float64, "i16": np.int16, "u8": np.uint8}
FLAGS = (0x2000, 0x7ffdfff, 0x1d, 0x2f3f40, 0x400)  # sub-volume, all but the centre, a fence, a cross, one
#: The foveated method's layers (SetMethod) with a reference; its fovea is checked against the layer's.
LAYERS = ("mip", "analytic", "demip")
#: DEMIP's projections (SetProjection), drawn for the DEMIP methods with random settings.
PROJECTIONS = ("mip", "mip", "lmip", "attenuated", "mida")
#: Grey windows, as fractions of the finite data range (None: OffscreenView's default).
WINDOWS = (None, None, (0.1, 0.6), (0.4, 0.45), (0.0, 0.05), (0.7, 1.0))
#: Methods whose picture is the float readout through the window's grey ramp: their pictures are checked too.
GREY = ("mip", "analytic", "minip", "analytic_minip", "average", "analytic_average")
#: The methods drawn with nearest-neighbour interpolation one case in five (those whose reference takes it).
NEAREST = ("mip", "minip", "average", "demip", "demip_two_pass")
#: Point-index units within which a sample half-way between two points is a tie under nearest-neighbour
#: interpolation: the GPU places samples in float32 (1e-5 until case 2942: a perspective ray of 100+ steps
#: through a volume placed by a scaling matrix, a sample 1e-5 to 3e-5 from half-way read the other point).
TIE = 3e-5
#: How far DEMIP's depth (in [0, 1]) may lie from the reference's: float32 rounding of the hit's position.
DEPTH_TOLERANCE = 1e-4
#: The directions a sample may be rounded to under nearest-neighbour interpolation, each axis on its own: the
#: nearest point either side of every half-way coordinate (an odd picture's centre ray in the front view is
#: half-way in x, y and, every few steps, z).
CORNERS = list(itertools.product((-1.0, 1.0), repeat=3))


def draw_case(rng: random.Random) -> dict:
    return dict(method=rng.choice(CHECKED + ["foveated"]), nan=rng.random() < 0.4, vectors=rng.random() < 0.25,
                dtype=rng.choice(list(TYPES)), anisotropic=rng.random() < 0.5, rotated=rng.random() < 0.3,
                extent=rng.random() < 0.3, slab=rng.random() < 0.3, mask=rng.random() < 0.3,
                bricks=rng.random() < 0.3, view=rng.choice(["oblique", "perspective", "front"]),
                crop=rng.random() < 0.3, clip=rng.random() < 0.3, flags=rng.choice(FLAGS),
                layer=rng.choice(LAYERS), gaze=(rng.uniform(0.3, 0.7), rng.uniform(0.3, 0.7)),
                tolerance=rng.choice([0.0, 0.0, 2.0, 8.0]), matrix=rng.random() < 0.25,
                component=rng.choice([None, None, 0, 2]), distance=rng.choice([None, None, 0.37, 1.9]),
                size=rng.choice([SIZE, (41, 37)]), window=rng.choice(WINDOWS),
                demip=dict(projection=rng.choice(PROJECTIONS), local_threshold=rng.choice([0.2, 0.5, 0.8]),
                           attenuation=rng.choice([0.0, 0.05, 0.3]), material_threshold=rng.choice([0.02, 0.1, 0.5])),
                cells=rng.random() < 0.15)


def volumes(case: dict, base: np.ndarray):
    """(the image drawn, the image the reference draws (the mask's points NaN), the mask or None)."""
    values = base.copy()
    if case["dtype"] == "i16":
        values = np.round(values * 1000 - 200)
    elif case["dtype"] == "u8":
        values = np.round(values * 250)
    values = values.astype(TYPES[case["dtype"]])
    if case["nan"] and case["dtype"] in ("f32", "f64"):
        values[5:14, 8:20, 3:12] = np.nan  # (z, y, x)
    array = np.stack([values, values * 0.5, values * 0.25], -1).reshape(-1, 3) if case["vectors"] else values.ravel()
    image = vtkImageData()
    cells = case.get("cells", False) and not case["mask"]  # (a mask hides points: refused with cell scalars)
    image.SetDimensions(*((25, 25, 25) if cells else (24, 24, 24)))  # cell scalars: drawn at the cell centres
    if case["anisotropic"]:
        image.SetSpacing(0.7, 1.0, 1.6)
    if case["rotated"]:
        c, s = np.cos(0.5), np.sin(0.5)
        image.SetDirectionMatrix(c, -s, 0, s, c, 0, 0, 0, 1)
    if case["extent"]:
        image.SetExtent(5, 28 + cells, -3, 20 + cells, 2, 25 + cells)
    image.SetOrigin(1.5, -2.0, 3.0)
    scalars = numpy_to_vtk(array, deep=True)
    scalars.SetName("s")
    (image.GetCellData() if cells else image.GetPointData()).SetScalars(scalars)
    if not case["mask"]:
        return image, image, None
    keep = np.ones(base.shape, bool)
    keep[:, :, 15:] = False
    mask = vtkImageData()
    mask.CopyStructure(image)
    mask.GetPointData().SetScalars(numpy_to_vtk(keep.ravel().astype(np.uint8), deep=True))
    hidden = array.astype(np.float64)
    hidden[~keep.ravel()] = np.nan
    reference_image = vtkImageData()
    reference_image.CopyStructure(image)
    holes = numpy_to_vtk(hidden, deep=True)
    holes.SetName("s")
    reference_image.GetPointData().SetScalars(holes)
    return image, reference_image, mask


def drawn_values(image, component) -> np.ndarray:
    """The values the methods draw of ``image`` (float64, flat): its component, or its vectors' magnitude."""
    values = vtk_to_numpy(image.GetPointData().GetScalars() or image.GetCellData().GetScalars()).astype(np.float64)
    if values.ndim == 2:
        values = values[:, component] if component is not None else np.linalg.norm(values, axis=1)
    return values


def case_window(case: dict, image, component) -> Optional[tuple]:
    """The case's grey window in data units (None: OffscreenView's default)."""
    if case.get("window") is None:
        return None
    values = drawn_values(image, component)
    low, span = np.nanmin(values), np.nanmax(values) - np.nanmin(values)
    return tuple(float(low + f * span) for f in case["window"])


def case_settings(case: dict) -> tuple:
    """(component, sample distance or None) of a case."""
    component = case.get("component") if case["vectors"] else None
    sampled = not METHODS[case["layer"] if case["method"] == "foveated" else case["method"]].walks_cells
    return component, case.get("distance") if sampled else None


def scene_for(case: dict, image, reference_image) -> OffscreenView:
    """A fresh scene drawing ``case`` (its window from ``reference_image``: the mask's points NaN)."""
    component, distance = case_settings(case)
    return OffscreenView(image, case["method"], size=case.get("size", SIZE), view=case["view"],
                         sample_distance=distance, component=component,
                         window=case_window(case, reference_image, component))


def replace_method(scene: OffscreenView, other: OffscreenView) -> None:
    """Draw ``scene``'s volume with ``other``'s mapper and method from now on (same volume, renderer, window)."""
    methods.detach(scene.mapper)
    methods.attach(other.mapper, scene.volume)
    scene.mapper, scene.method = other.mapper, other.method


def change_scene(scene: OffscreenView, case: dict, image, reference_image) -> None:
    """Change a scene that drew another case to draw ``case``: what OffscreenView's constructor sets."""
    component, distance = case_settings(case)
    scene.set_input(image, component)
    scene.sample_distance = distance or min(abs(s) for s in image.GetSpacing())
    scene.mapper.SetSampleDistance(scene.sample_distance)
    scene.set_window(resolve_window(window_image(image, component, None),
                                    case_window(case, reference_image, component),
                                    scene.method.projection))
    scene.size = case.get("size", SIZE)
    scene.render_window.SetSize(*scene.size)
    scene.volume.SetOrientation(0.0, 0.0, 0.0)
    scene.volume.SetScale(1.0, 1.0, 1.0)
    scene.volume.SetPosition(0.0, 0.0, 0.0)
    set_view(scene.renderer, scalar_image(image), case["view"])


def configure(scene: OffscreenView, case: dict, number: int, image, mask, reset: bool = False) -> tuple:
    """Apply the case's matrix and mapper settings (``reset``: undo another case's first); returns
    (clip planes for the reference, cropping, matrix, DEMIP settings)."""
    mapper, camera = scene.mapper, scene.camera
    if reset:
        mapper.RemoveAllClippingPlanes()
        mapper.SetCropping(False)
        mapper.SetSlabThickness(0.0)
        mapper.SetMaskInput(None)
        scene.render_window.SetMultiSamples(0)
        object_state(mapper).pop("texture_limit", None)  # asked of the driver again
    matrix = None
    if case.get("matrix"):  # the volume placed by its own matrix (a clinical pipeline's, ParaView's transform)
        scene.volume.SetOrientation(20.0, -35.0, 10.0)
        scene.volume.SetScale(1.0, 1.3, 0.8)
        scene.volume.SetPosition(4.0, -3.0, 2.0)
        scene.renderer.ResetCamera()
        matrix = scene.volume.GetMatrix()
    foveated = case["method"] == "foveated"
    if foveated:  # its fovea: the layer method at full quality, against the layer's reference
        mapper.SetMethod(case["layer"])
        mapper.SetGazePoint(*case["gaze"])
        mapper.SetContentTolerance(case["tolerance"])
    name = case["layer"] if foveated else case["method"]
    settings = {}
    if name in ("demip", "demip_two_pass") and "demip" in case and not foveated:  # projections, thresholds
        settings = dict(case["demip"], **demip_look_case(number))
        if name == "demip_two_pass":
            settings["projection"] = "mip"  # (the two-pass variant draws MIP's maximum)
        for key, value in settings.items():
            getattr(mapper, "Set" + "".join(part.capitalize() for part in key.split("_")))(value)
    if mask is not None:
        mapper.SetMaskInput(mask)
    framing = camera_case(case, number)
    if framing == "shift":  # an off-centre window (a tiled display's tile, ParaView's image reduction)
        draw = random.Random(number + 5000)
        camera.SetWindowCenter(draw.uniform(-0.6, 0.6), draw.uniform(-0.6, 0.6))
    elif framing == "inside":  # the eye inside the volume (a fly-through): the near plane cuts the box
        bounds = np.array(scene.volume.GetBounds())
        radius = 0.5 * np.linalg.norm(bounds[1::2] - bounds[0::2])
        camera.Dolly(camera.GetDistance() / (0.35 * radius))
        scene.renderer.ResetCameraClippingRange()
    planes, cropping = [], None
    if case["slab"]:
        mapper.SetSlabThickness(7.0)
        planes.append(slab_planes(7.0, camera.GetFocalPoint(), camera.GetDirectionOfProjection()))
    if case["crop"]:
        bounds, draw = image.GetBounds(), random.Random(number + 1000)
        faces = []
        for axis in range(3):
            low, width = bounds[2 * axis], bounds[2 * axis + 1] - bounds[2 * axis]
            faces += [low + width * draw.uniform(0.1, 0.4), low + width * draw.uniform(0.6, 0.9)]
        mapper.SetCropping(True)
        mapper.SetCroppingRegionPlanes(*faces)
        mapper.SetCroppingRegionFlags(case["flags"])
        cropping = (tuple(faces), case["flags"])
    if case["clip"]:
        draw = random.Random(number + 2000)
        centre, normal = np.array(image.GetCenter()), np.array([draw.uniform(-1, 1) for _ in range(3)])
        normal /= np.linalg.norm(normal)
        plane = vtkPlane()
        plane.SetOrigin(*centre)
        plane.SetNormal(*normal)
        mapper.AddClippingPlane(plane)
        planes.append((centre[None, :], normal[None, :]))
    if case["bricks"]:
        object_state(mapper)["texture_limit"] = 12  # pretend a small GPU
    if nearest_case(case, number):  # the volume property's nearest-neighbour interpolation
        scene.volume.GetProperty().SetInterpolationTypeToNearest()
    if multisample_case(number):  # a window drawing with MSAA (pyvista's default: 8 samples)
        scene.render_window.SetMultiSamples(4)
    transfer = transfer_case(case, number)
    if transfer is not None:  # a colour map and opacity of the user's (pyvista's cmap and opacity)
        scene.volume.SetProperty(transfer_property(transfer, scene.window))
    return planes, cropping, matrix, settings


def camera_case(case: dict, number: int):
    """How case ``number``'s camera is framed beyond its view: ``"shift"`` (an off-centre window,
    ``SetWindowCenter``), ``"inside"`` (a perspective eye inside the volume) or None; drawn apart from the
    case, so that every other draw stays as it was."""
    draw = random.Random(number + 4000).random()
    if draw < 0.15:
        return "shift"
    return "inside" if draw < 0.35 and case["view"] == "perspective" else None


def demip_look_case(number: int) -> dict:
    """DEMIP's depth mode, depth weight, colour sphere and chromadepth for case ``number`` (drawn apart from
    the case, so that every other draw stays as it was)."""
    draw = random.Random(number + 6000)
    return dict(depth_mode=draw.choice(DEMIPVolumeMapper.DEPTH_MODES), depth_weight=draw.choice([0.15, 0.5, 1.0]),
                sphere_weight=draw.choice([0.0, 0.0, 0.4, 1.0]),
                sphere_orientation=tuple(draw.uniform(-180.0, 180.0) for _ in range(3)),
                chroma_depth_weight=draw.choice([0.0, 0.0, 0.0, 0.6]))


def multisample_case(number: int) -> bool:
    """Whether case ``number``'s window draws with MSAA (4 samples), one case in four (drawn apart from the
    case, so that every other draw stays as it was)."""
    return random.Random(number + 8000).random() < 0.25


def inside_pixels(number: int, *drawn: np.ndarray) -> np.ndarray:
    """The pixels whose picture is checked: with MSAA those whose 3x3 neighbourhood each of ``drawn`` (the
    reference's values, the GPU's float readout: NaN where nothing is drawn) draws all or nothing of (MSAA
    blends a silhouette pixel's colour by the part of it the box covers; a ray grazing an edge-on face may be
    a hit in one and not the other); else all."""
    shape = drawn[0].shape
    if not multisample_case(number):
        return np.ones(shape, bool)
    inside = np.ones(shape, bool)
    for values in drawn:
        hit = np.isfinite(values)
        padded = np.pad(hit, 1, constant_values=False)  # (the box's edge may lie in the picture's last pixel)
        inside &= np.all([padded[dy:dy + shape[0], dx:dx + shape[1]] == hit for dy in range(3) for dx in range(3)],
                         axis=0)
    return inside


def transfer_case(case: dict, number: int) -> Optional[tuple]:
    """A colour map and opacity for case ``number``, ``(colour points, opacity points)``, each point ``(x, ...)``
    with ``x`` a place in the window (0 its low end, 1 its high end), or None (the grey ramp, opaque): the grey
    methods (not foveated, not under nearest interpolation), one case in two, drawn apart from the case, so
    that every other draw stays as it was."""
    demip = (case["method"] == "demip_two_pass" or (case["method"] == "demip" and case["demip"]["projection"] != "mida")) \
        and case["dtype"] != "u8"  # (MIDA composites its own colours: its reference is grey)
    if (case["method"] not in GREY and not demip) or nearest_case(case, number):
        return None
    draw = random.Random(number + 7000)
    if draw.random() < 0.5:
        return None
    colours = sorted((draw.uniform(-0.1, 1.1), draw.random(), draw.random(), draw.random())
                     for _ in range(draw.randint(2, 5)))
    step = draw.uniform(0.2, 0.8)
    shapes = [((0.0, 0.0), (1.0, 1.0)),  # a ramp
              ((0.0, 0.0), (0.4, 0.05), (0.5, 0.5), (0.6, 0.95), (1.0, 1.0)),  # a sigmoid
              ((step - 0.001, 0.0), (step + 0.001, 1.0)),  # a step
              ((0.0, 1.0), (0.5, 0.0), (1.0, 1.0)),  # a V: the middle transparent
              ((0.3, 0.0), (0.35, 1.0), (0.65, 1.0), (0.7, 0.0)),  # a band
              ((0.0, 0.5), (1.0, 0.5))]  # half transparent
    if demip:  # (DEMIP's colour is checked at the value, not over its tolerance: no step)
        del shapes[2]
    return colours, draw.choice(shapes)


def transfer_property(transfer: tuple, window) -> vtkVolumeProperty:
    """The volume property of :func:`transfer_case`'s points placed in ``window`` (linear interpolation)."""
    low, high = window
    colour, opacity = vtkColorTransferFunction(), vtkPiecewiseFunction()
    for x, r, g, b in transfer[0]:
        colour.AddRGBPoint(low + x * (high - low), r, g, b)
    for x, a in transfer[1]:
        opacity.AddPoint(low + x * (high - low), a)
    prop = vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetInterpolationTypeToLinear()
    return prop


def demip_window(scene: OffscreenView, case: dict, number: int):
    """DEMIP's window: the grey window, or under :func:`transfer_case`'s functions where they stop being
    constant (the mapper's, ``transfer_bounds.constant_ends`` over the drawn scalars' range); None where they
    are constant over it (no DEMIP term)."""
    if transfer_case(case, number) is None:
        return scene.window
    scalars = scene.mapper.GetRenderedInput().GetPointData().GetScalars()
    ends = constant_ends(scene.volume.GetProperty(), *scalars.GetRange(0))
    return ends if ends[1] > ends[0] else None


def transfer_extremes(transfer: tuple, window, low_values: np.ndarray, high_values: np.ndarray) -> tuple:
    """(least, greatest) straight colour, shape (..., 3), and (least, greatest) opacity, shape (..., 1), of
    :func:`transfer_case`'s functions over each value interval (float64, the functions piecewise linear and
    clamped, as VTK's: their extremes lie at the interval's ends or the points inside it)."""
    low, high = window
    places = [np.array([low + point[0] * (high - low) for point in points]) for points in transfer]
    colours, opacity = (np.array([point[1:] for point in points]) for points in transfer)
    inside = [np.clip(x, low_values, high_values) for x in np.concatenate(places)]
    samples = np.stack([low_values, high_values] + inside, axis=-1)  # (..., n): the ends, the points clipped in
    rgb = np.stack([np.interp(samples, places[0], colours[:, channel]) for channel in range(3)], axis=-1)
    alpha = np.interp(samples, places[1], opacity[:, 0])[..., None]
    return rgb.min(axis=-2), rgb.max(axis=-2), alpha.min(axis=-2), alpha.max(axis=-2)


def transfer_span(transfer: tuple, window, low_values: np.ndarray, high_values: np.ndarray) -> tuple:
    """(least, greatest) premultiplied colour, shape (..., 3), of :func:`transfer_case`'s functions over each
    value interval (:func:`transfer_extremes`); 0 where the interval is NaN (a ray that drew nothing)."""
    least_rgb, greatest_rgb, least_alpha, greatest_alpha = transfer_extremes(transfer, window, low_values,
                                                                             high_values)
    missed = np.isnan(low_values)[..., None]
    return np.where(missed, 0.0, least_rgb * least_alpha), np.where(missed, 0.0, greatest_rgb * greatest_alpha)


def nearest_case(case: dict, number: int) -> bool:
    """Whether case ``number`` draws with nearest-neighbour interpolation: a sampled projection with a
    reference for it, one in five (drawn apart from the case, so that every other draw stays as it was)."""
    return case["method"] in NEAREST and random.Random(number + 3000).random() < 0.2


def tied_nearest(values: np.ndarray, position: np.ndarray, pick) -> np.ndarray:
    """``pick`` (np.minimum, np.maximum) of the nearest point's value at every :data:`CORNERS` offset of
    ``position``: one bound of what a sample within float rounding of half-way between points may read."""
    return functools.reduce(pick, [rays.nearest(values, position + TIE * np.array(signs)) for signs in CORNERS])


def run_case(number: int, base: np.ndarray, after: Optional[int] = None) -> tuple:
    """(case, problem or None).  ``after``: the scene first draws case ``after`` (with case ``number``'s
    method, or for ``number`` a multiple of 3 its own, the volume's mapper then replaced by one of case
    ``number``'s method), then is changed to case ``number`` (input, window, view, size, sample distance,
    matrix and every mapper setting), keeping its volume and window, as an interactive viewer does; for odd
    ``number`` the input is the first image object, given case ``number``'s contents by ``DeepCopy``."""
    case = draw_case(random.Random(number))
    image, reference_image, mask = volumes(case, base)
    component = case_settings(case)[0]
    values = drawn_values(reference_image, component)
    span = np.nanmax(values) - np.nanmin(values)
    nearest = nearest_case(case, number)
    if after is None:
        scene = scene_for(case, image, reference_image)
    else:  # the scene drew another case first, then is changed to this one
        first = draw_case(random.Random(after))
        if number % 3:  # else the first case's own method: the volume's mapper is replaced (ParaView's Method)
            first["method"] = case["method"]
        other = np.ascontiguousarray(base.transpose(2, 1, 0)[::-1])  # other contents: stale state shows
        first_image, first_reference, first_mask = volumes(first, other)
        scene = scene_for(first, first_image, first_reference)
        configure(scene, first, after, first_image, first_mask)
        scene.float_image()
        scene.screenshot()
        if number % 2:  # odd cases: the same image object given the new contents (a time step read in place)
            first_image.DeepCopy(image)
            image = first_image
        if first["method"] != case["method"]:
            replace_method(scene, scene_for(case, image, reference_image))
        change_scene(scene, case, image, reference_image)
    planes, cropping, matrix, settings = configure(scene, case, number, image, mask, reset=after is not None)
    mapper, camera = scene.mapper, scene.camera
    foveated = case["method"] == "foveated"
    name = case["layer"] if foveated else case["method"]
    size = scene.size
    got = scene.float_image()
    if foveated:
        plan = mapper.GetLastPlan()
        outside = foveation.eccentricity(size, plan.gaze, plan.aspect) >= plan.start
        got[outside] = np.nan
    clip = (np.concatenate([p[0] for p in planes]), np.concatenate([p[1] for p in planes])) if planes else None
    if nearest:
        settings["interpolation"] = "nearest"
    window = demip_window(scene, case, number) if name in ("demip", "demip_two_pass") else scene.window
    if window is None:  # (transfer functions constant over the data: nothing to compare)
        return case, None
    the_reference = functools.partial(METHODS[name].reference, reference_image, camera, scene.size,
                                      sample_distance=scene.sample_distance, window=window, clip_planes=clip,
                                      cropping=cropping, matrix=matrix, **settings,
                                      **({"component": component} if component is not None else {}))
    expected = the_reference()
    if nearest:  # a sample within float rounding of half-way between two points is a tie: either point's
        # value may count, sample by sample, each tied axis on its own: the reductions of the lowest and of
        # the highest of the values at the candidate points bound every choice of the maximum and minimum;
        # expected is got moved into the span of those two and the plain reference. Not every value is
        # monotone in the picks: the lowest picks may give the higher value (DEMIP's LMIP: its scan ends
        # later, case 1468; the mean with missing points: a pick of a missing point drops the sample, 2443)
        bounds = []
        for pick in (np.minimum, np.maximum):
            reference.nearest = reference_demip.nearest = functools.partial(tied_nearest, pick=pick)
            try:
                bounds.append(the_reference())
            finally:
                reference.nearest = reference_demip.nearest = rays.nearest
        candidates = np.stack([expected, *bounds])
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # (rays that miss: all NaN)
            low, high = np.nanmin(candidates, axis=0), np.nanmax(candidates, axis=0)
        expected = np.where(np.isnan(got), expected, np.clip(got, low, high))
    if foveated:
        expected[outside] = np.nan
    agree = np.mean(np.isnan(got) == np.isnan(expected))
    both = np.isfinite(got) & np.isfinite(expected)
    errors = np.abs(got[both] - expected[both]) / span
    error = float(errors.max()) if both.any() else 0.0
    tolerance = METHODS[name].reference_tolerance
    if case["dtype"] == "u8" and not METHODS[name].walks_cells:
        tolerance = max(tolerance, 2.0 / 250.0)
    if foveated and case["tolerance"] > 0:
        # content-adaptive: the fovea within 1 grey of full quality wherever a structure is above the window's
        # floor (issue 17); background there may be interpolated from coarser rays, within the tolerance
        low, high = scene.window
        structure = both & (expected >= low)
        errors = np.abs(got - expected)[structure] / (high - low)  # of the window
        tolerance = max(1.0 / 255.0, tolerance * span / (high - low))  # (the layer's own on 8-bit data)
        error = float(errors.max()) if errors.size else 0.0
        agree = max(agree, 1.0)  # (hit and miss: the interpolated background's, not the reference's)
    problem = mapper.GetLastProblem() if hasattr(mapper, "GetLastProblem") else None
    if problem or agree <= 0.97 or error > tolerance:
        return case, (f"{problem or ''} hit/miss agree {agree:.3f}, error {error:.3g} of the range "
                      f"(tolerance {tolerance:g}) at {int((errors > tolerance).sum())} of {int(both.sum())} pixels")
    if name in ("demip", "demip_two_pass") and not foveated and not nearest:
        slab = (7.0, camera.GetFocalPoint(), camera.GetDirectionOfProjection()) if case["slab"] else None
        rendered = functools.partial(reference.render, reference_image, camera, scene.size, "demip",
                                     sample_distance=scene.sample_distance, clip_planes=clip, slab=slab,
                                     cropping=cropping, matrix=matrix, **settings,
                                     **({"component": component} if component is not None else {}))
        problem = demip_problem(scene, case, number, rendered, window, got, span, tolerance)
        if problem:
            return case, problem
    if name in GREY and not foveated and not nearest:  # the picture: the reference through
        # the window's grey ramp (block skipping starts rays at the window's floor, the float readout does not).
        # Not under nearest-neighbour interpolation: VTK reads the colour table nearest too, its colours step
        # between the table's entries (docs/reliability.md, "Blend modes"); the floats are checked
        low, high = scene.window
        transfer = transfer_case(case, number)
        if transfer is not None:  # the reference through the colour and opacity functions, over black: within
            # 2 grey of their span over the value's tolerance and one step of VTK's table (at least 1024 texels
            # over the texture's range, at most twice the data's with missing values filled below)
            reach = tolerance * span + 2.0 * span / 1023.0
            least, greatest = transfer_span(transfer, scene.window, expected - reach, expected + reach)
            picture = scene.screenshot().astype(float)
            outside = np.maximum(255.0 * least - picture, picture - 255.0 * greatest).max(axis=-1)
            off = (outside > 2.0) & inside_pixels(number, expected, got)
            if off.mean() > 0.01:
                return case, (f"picture ({transfer}): {int(off.sum())} pixels more than 2 grey off the reference's "
                              f"colours, up to {outside.max():.0f}")
            return case, None
        grey = np.where(np.isnan(expected), 0.0, np.round(np.clip((expected - low) / (high - low), 0.0, 1.0) * 255))
        allowed = 2.0 + 255.0 * (tolerance - METHODS[name].reference_tolerance) * span / (high - low)
        off = (np.abs(scene.screenshot()[..., 0].astype(float) - grey) > allowed) & inside_pixels(number, expected,
                                                                                                   got)
        if off.mean() > 0.01:
            return case, f"picture: {int(off.sum())} pixels more than {allowed:.3g} grey off the reference's"
    return case, None


def demip_problem(scene: OffscreenView, case: dict, number: int, rendered, window, readout: np.ndarray,
                  span: float, tolerance: float) -> Optional[str]:
    """Why DEMIP's depth (its readout "depth") or picture disagrees with the float64 reference's, or None.
    ``rendered``: ``reference.render`` bound to the case's scene, "demip" and settings; ``window``: DEMIP's
    (:func:`demip_window`); ``readout``: the float readout; ``span``, ``tolerance``: the drawn values' range and
    the value's tolerance (of it)."""
    mapper = scene.mapper
    transfer = transfer_case(case, number)

    def reference_demip_output(output, material_threshold, move=0.0, colour="grey"):
        return rendered(output=output, window=np.add(window, move), material_threshold=material_threshold,
                        colour=colour)

    # the depth is of the first sample above the window's floor whose material lies within the threshold of
    # the maximum's: a sample within the value's tolerance of either bound is a tie (8-bit data: the texture
    # unit's 8-bit filtering). Depth falls as the threshold widens and as the window moves down: the
    # threshold widened with the window moved down by the tolerance, and the reverse, bound every choice
    threshold = mapper.GetMaterialThreshold()
    low, high = window
    move = tolerance * span
    bounds = ((threshold, 0.0), (min(threshold + move / (high - low), 1.0), -move),
              (max(threshold - move / (high - low), 1e-6), move))
    if mapper.GetProjection() not in ("attenuated", "mida"):  # (those draw no DEMIP term, no depth)
        candidates = np.stack([reference_demip_output("depth", *bound) for bound in bounds])
        got = render_depth(scene.render_window, mapper)
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # (rays with no DEMIP term: all NaN)
            # where the tightened bounds leave a ray no term (its maximum a tie at the floor), any later
            # sample may be the first to count
            latest = np.where(np.isnan(candidates).any(axis=0), np.inf, np.nanmax(candidates, axis=0))
            nearest = np.clip(got, np.nanmin(candidates, axis=0), latest)
        expected = np.where(np.isnan(got), candidates[0], nearest)
        agree = np.mean(np.isnan(got) == np.isnan(expected))
        both = np.isfinite(got) & np.isfinite(expected)
        errors = np.abs(got[both] - expected[both])
        off = int((errors > DEPTH_TOLERANCE).sum())
        if agree <= 0.99 or off > max(1, 0.01 * both.sum()):
            return (f"depth ({mapper.GetDepthMode()}): term/no term agree {agree:.3f}, {off} of "
                    f"{int(both.sum())} pixels more than {DEPTH_TOLERANCE:g} off, up to "
                    f"{errors.max() if errors.size else 0:.3g}")
    # the picture: each pixel within 2 grey (and the value's tolerance through the window) of the span of the
    # references' colours at the bounds above (a tied sample moves the depth, and with it the colour)
    if transfer is None:
        references = np.stack([reference_demip_output("rgb", *bound) for bound in bounds])  # NaN: the ray misses
    else:  # the base colour, then the opacity of the ray's value (premultiplied, over black), as
        # shaders/demip_color.glsl writes them, each at its least and greatest over the value's tolerance and
        # one step of VTK's tables (the DEMIP terms are monotone in the base colour)
        reach = tolerance * span + 2.0 * span / 1023.0

        def base(pick):
            return lambda v: transfer_extremes(transfer, scene.window, v - reach, v + reach)[pick]

        value = reference_demip_output("value", *bounds[0])
        _, _, least, greatest = transfer_extremes(transfer, scene.window, value - reach, value + reach)
        references = np.stack([reference_demip_output("rgb", *bound, colour=base(0)) * least for bound in bounds]
                              + [reference_demip_output("rgb", *bound, colour=base(1)) * greatest
                                 for bound in bounds])
    colours = np.round(255.0 * np.nan_to_num(references))
    allowed = 2.0 + 255.0 * (tolerance - METHODS[case["method"]].reference_tolerance) * span / (high - low)
    picture = scene.screenshot()[..., :3].astype(float)
    outside = np.maximum(colours.min(axis=0) - picture, picture - colours.max(axis=0)).max(axis=-1)
    wrong = (outside > allowed) & inside_pixels(number, references[0][..., 0], readout)
    if wrong.mean() > 0.01:
        return f"picture: {int(wrong.sum())} pixels more than {allowed:.3g} grey off, up to {outside.max():.0f}"
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--first", type=int, default=0)
    parser.add_argument("--count", type=int, default=60)
    parser.add_argument("--cases", type=int, nargs="*", help="these case numbers only")
    parser.add_argument("--after", type=int, help="draw case N on a scene that drew case N + AFTER first (its "
                        "method N's), then was changed: what a viewer's settings leave behind")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    base = vtk_to_numpy(make_fixture("vessels", size=24).GetPointData().GetScalars()).astype(np.float64)
    base = base.reshape(24, 24, 24)
    off = 0
    numbers = args.cases or range(args.first, args.first + args.count)
    for number in numbers:
        case, problem = run_case(number, base, None if args.after is None else number + args.after)
        if problem:
            off += 1
            print(f"case {number}: {problem}\n    {case}")
    print(f"{len(numbers)} cases, {off} off")


if __name__ == "__main__":
    main()

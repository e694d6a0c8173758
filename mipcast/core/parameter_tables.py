"""Every method's parameter table: the one definition of each user parameter.

The mappers' ``SetX``/``GetX`` and uniform uploads, the float64 references'
argument checks, the command line, the viewer's sliders and ParaView's
properties are all derived from these tuples (see
:class:`mipcast.core.parameters.Parameter`).  A mapper's internal setters
(e.g. analytic MIP's shared corner packer) are not parameters.

Examples
--------
>>> [p.name for p in DEMIP][:3]
['depth_weight', 'material_threshold', 'depth_mode']
>>> {p.name: p.default for p in FOVEATED}["number_of_levels"]
3
"""
from __future__ import annotations

from mipcast.core import foveation, shading
from mipcast.core.parameters import Parameter, Uniform
from mipcast.core.validation import check_finite

def _slab_point(*values):
    """None, or three finite numbers (a point or a direction) as a tuple."""
    if len(values) == 1 and (values[0] is None or isinstance(values[0], (tuple, list))):
        values = values[0]
    if values is None or len(values) == 0:
        return None
    if len(values) != 3:
        raise TypeError(f"give three numbers (x, y, z) or None, got {values!r}")
    return tuple(check_finite("slab point", v) for v in values)


def _slab_normal(*values):
    normal = _slab_point(*values)
    if normal is not None and not any(normal):
        raise ValueError("slab_normal must not be (0, 0, 0); None follows the view direction")
    return normal


#: The slab, shared by every method that renders a view (appended to each of
#: their tables): only the part of each ray between two parallel planes
#: counts.  Mapper-level planes, uploaded per render as uniforms
#: (mipcast/mappers/clip_uniforms.py): moving the slab never rebuilds a shader.
SLAB = (
    Parameter("slab_thickness", "float", 0.0,
              "Thickness of the slab, in world units (mm for DICOM): only the part of each ray between two "
              "planes this far apart counts (0: the whole volume). Going from 0 to a slab (or back) installs "
              "the clipping piece (one compile each way); changing a slab's thickness does not.",
              low=0.0, unit="world units", pieces=True),
    Parameter("slab_centre", "value", None,
              "A point (x, y, z) on the slab's mid-plane, in world coordinates; None: the camera's focal "
              "point (the slab follows the camera).", convert=_slab_point, variadic=True, unit="world units"),
    Parameter("slab_normal", "value", None,
              "The slab's normal (x, y, z), world coordinates; None: the view direction (the slab faces "
              "the camera).", convert=_slab_normal, variadic=True),
)

#: Sampled MIP (VTK's sample distance, image sample distance and jittering
#: apply): block skipping, and the slab.
MIP = (
    Parameter("skipping", "bool", True,
              "Skip samples that cannot change the answer (False only to measure what it saves). True: with "
              "a transfer-function floor above the data minimum (a window above the background) the running "
              "maximum starts at the floor, the ray jumps over blocks of cells whose maximum is not above it "
              "and stops at the ceiling; the same picture. False: every sample is read.", pieces=True),
) + SLAB

#: Sampled MinIP: block skipping mirrored (block minima, the ceiling), and the slab.
MINIP = (
    Parameter("skipping", "bool", True,
              "Skip samples that cannot change the answer (False only to measure what it saves). True: with "
              "a transfer-function ceiling below the data maximum (a window below the tissue, as for airways) "
              "the running minimum starts at the ceiling, the ray jumps over blocks of cells whose minimum is "
              "not below it and stops at the floor; the same picture. False: every sample is read.", pieces=True),
) + SLAB

#: The other sampled projections (average, new hook pieces) have no parameters
#: of their own besides the slab.
SAMPLED = SLAB

ANALYTIC = (
    Parameter("packed_corners", "bool", True,
              "Read four corners per texel from a packed copy of the volume. "
              "True: two texture fetches per cell, four times the texture memory; "
              "False: the volume's own one-component texture, eight fetches per cell.", pieces=True),
    Parameter("skipping", "bool", True,
              "Skip work that cannot change the answer (False only to measure what it saves). "
              "True: no cubic for cells whose corners are not above the running maximum, the "
              "block-maximum jumps and the transfer-function floor and ceiling; False: every "
              "crossed cell is fetched and solved. Both are exact.",
              uniforms=(Uniform("u_mc_cornerBound", "float", lambda v, s: 1.0 if v else 0.0),), pieces=True),
) + SLAB


def _local_threshold(value, settings) -> float:
    """LMIP's threshold as a normalised scalar; far above every value when LMIP is off."""
    if settings["projection"] != "lmip":
        return 1.0e30
    return settings["floor"] + value * (settings["ceiling"] - settings["floor"])


#: DEMIP's settings and the slab: two-pass DEMIP's table (its first pass marches every sample), and
#: what DEMIP's bricks follow.
DEMIP_SETTINGS = (
    Parameter("depth_weight", "float", 0.15,
              "Weight d_w of the depth term in Eq. 1 (the paper's default 0.15). "
              "0 is plain MIP; larger values brighten near and darken far structures.",
              low=0.0, high=1.0, uniforms=(Uniform("u_mc_depthWeight"),)),
    Parameter("material_threshold", "float", 0.1,
              "How close in material (a fraction of the window) counts as the maximum's material, eps. "
              "Near 0 the depth is that of the maximum's own sample (noisy on noisy data); 1 accepts "
              "the first sample above the floor.", low=0.0, high=1.0, open_low=True, unit="of the window",
              uniforms=(Uniform("u_mc_materialThreshold", "float",
                                lambda v, s: v if s["depth_of"] == "same_material" else 0.0),)),
    Parameter("depth_mode", "choice", "entry_plus_length",
              "How depth is measured: the window depth of the hit, the steps inside the box, the entry's "
              "depth plus the ray length to the hit (the paper's choice), or the exact eye distance.",
              choices=shading.DEPTH_MODES,
              uniforms=(Uniform("u_mc_depthMode", "int", lambda v, s: shading.DEPTH_MODES.index(v)),)),
    Parameter("sphere_weight", "float", 0.0,
              "Weight sph_w of the colour sphere in Eq. 2 (0: off).", low=0.0, high=1.0,
              uniforms=(Uniform("u_mc_sphereWeight"),)),
    Parameter("sphere_colors", "value", shading.SPHERE_PRESETS["red-blue"],
              "The sphere's front and back colour: a preset (red-blue, green-red, green-blue) or two RGB "
              "triplets in [0, 1], e.g. SetSphereColors((1, 0.5, 0), (0, 0.6, 1)), or six numbers "
              "(--sphere-colors 1 0.5 0 0 0.6 1).", convert=lambda *c: shading.sphere_colors(c), variadic=True,
              uniforms=(Uniform("u_mc_sphereFront", "vec3", lambda v, s: list(v[0])),
                        Uniform("u_mc_sphereBack", "vec3", lambda v, s: list(v[1])))),
    Parameter("sphere_orientation", "value", shading.IDENTITY,
              "Rotate the colour sphere in world coordinates (camera and volume unaffected): three angles "
              "in degrees (Rz @ Ry @ Rx: about x first) or a 3x3 rotation matrix. Its front pole points "
              "along the matrix's third column; (0, 180, 0) swaps front and back.",
              convert=lambda *r: shading.rotation(r), variadic=True, unit="degrees",
              uniforms=(Uniform("u_mc_sphereAxis", "vec3", lambda v, s: [row[2] for row in v]),)),
    Parameter("chroma_depth_weight", "float", 0.0,
              "Weight of pseudo-chromadepth colouring (Ropinski et al.; 0: off): after Eq. 1 and 2 the "
              "colour moves towards a hue running from red (near) to blue (far). For pseudo-chromadepth on "
              "plain MIP use depth_weight 0 and depth_of 'maximum'.", low=0.0, high=1.0,
              uniforms=(Uniform("u_mc_chromaWeight"),)),
    Parameter("depth_of", "choice", "same_material",
              "Which sample gives the depth: the first of the maximum's material (DEMIP), or the first "
              "sample whose material equals the maximum's (the maximum itself; eps is then ignored).",
              choices=shading.DEPTH_OF),
    Parameter("projection", "choice", "mip",
              "The ray's value: the maximum (DEMIP), local MIP (the first local maximum above "
              "local_threshold), attenuated MIP (napari-style), or MIDA (gamma 0); the last two draw no "
              "DEMIP term. Switching installs other shader pieces (one compile each).",
              choices=shading.PROJECTIONS, pieces=True),
    Parameter("local_threshold", "float", 0.5,
              "LMIP's threshold as a material (place in the window).", low=0.0, high=1.0, unit="of the window",
              uniforms=(Uniform("u_mc_localThreshold", "float", _local_threshold),)),
    Parameter("attenuation", "float", 0.05,
              "Attenuated MIP's attenuation per voxel of full material (0 gives the MIP picture).",
              low=0.0, unit="per voxel", uniforms=(Uniform("u_mc_attenuation"),)),
) + SLAB

#: DEMIP in one pass: its settings, the slab and block skipping (projection "mip").
DEMIP = DEMIP_SETTINGS + (
    Parameter("skipping", "bool", True,
              "Skip samples that cannot change the answer (False only to measure what it saves). True: with "
              "a transfer-function floor above the data minimum, the maximum's march (projection 'mip') "
              "starts at the floor, jumps over blocks of cells whose maximum is not above it and ends after "
              "the ceiling; the same picture and depth. LMIP, attenuated MIP and MIDA read every sample.",
              pieces=True),
)


def _gaze_point(*xy) -> tuple:
    if len(xy) == 1 and isinstance(xy[0], (tuple, list)):
        xy = tuple(xy[0])
    if len(xy) != 2:
        raise TypeError(f"gaze_point takes x and y (normalised viewport coordinates), got {xy!r}")
    return check_finite("x", xy[0]), check_finite("y", xy[1])


def _region(region):
    if region is None:
        return None
    values = [check_finite("region", v) for v in region]
    if len(values) == 3:
        values = [values[0], values[0], values[1], values[1], values[2], values[2]]
    if len(values) != 6 or any(values[2 * i] > values[2 * i + 1] for i in range(3)):
        raise ValueError("region must be a point (x, y, z) or bounds (x0, x1, y0, y1, z0, z1) "
                         f"with x0 <= x1 etc., got {tuple(region)!r}")
    return tuple(values)


#: Names of the methods a foveated mapper can draw its levels with; filled
#: from the method table (:data:`mipcast.methods.METHODS`, capability
#: ``foveation_layer``) when :mod:`mipcast.methods` is imported.
FOVEATION_LAYERS: dict = {}

FOVEATED = (
    Parameter("method", "choice", "mip", "The mipcast method every level renders with.",
              choices=lambda: tuple(FOVEATION_LAYERS)),
    Parameter("gaze_point", "value", (0.5, 0.5),
              "Look at (x, y) in normalised viewport coordinates ((0, 0) bottom-left). Points outside "
              "[0, 1] are allowed (the fovea is then partly or wholly off screen). Stops following the "
              "mouse or a region of interest.", convert=_gaze_point, variadic=True),
    Parameter("foveal_radius", "float", foveation.DEFAULT_RADIUS,
              "Radius of full quality around the gaze, in viewport heights.", low=0.0,
              unit="viewport heights", numbers_only=False),
    Parameter("falloff", "float", foveation.DEFAULT_FALLOFF,
              "Eccentricity from the fovea's edge to the coarsest level, in viewport heights. The ray "
              "spacing grows linearly from 1 to 2**(levels - 1) pixels over this width (the acuity "
              "schedule); 0 switches levels abruptly (visible seams).", low=0.0,
              unit="viewport heights", numbers_only=False),
    Parameter("number_of_levels", "int", foveation.DEFAULT_LEVELS,
              "Image pyramid levels, 1 (full quality only) to 5 (rays every 16 pixels).", low=1, high=5),
    Parameter("foveation", "bool", True, "False: the method at full quality everywhere (one level, no blending)."),
    Parameter("region_of_interest", "value", None,
              "Keep a world-space region sharp: a point (x, y, z) or bounds (x0, x1, y0, y1, z0, z1). At "
              "every render the gaze moves to the region's projected centre and the foveal radius grows "
              "(never shrinks) to cover its projection; None returns to the last gaze point.",
              convert=lambda region: _region(region), unit="world units"),
    Parameter("peripheral_sampling", "choice", "footprint",
              "How peripheral levels sample along their rays: no farther apart than the level's rays "
              "(footprint, default), the paper's one level per image level (level), or full-quality "
              "sampling (rays).", choices=foveation.SAMPLING_POLICIES),
    Parameter("content_tolerance", "float", 0.0,
              "Content-adaptive ray density, in grey levels (0 = off). A level one step coarser than "
              "acuity's coarsest is cast over the whole view first; acuity's coarsest level then casts "
              "only where that picture's neighbouring values differ by more than this (and over the whole "
              "fovea), and a finer ray only where acuity's coarsest picture differs by more than this, "
              "or, inside the fovea, shows structure (above the transfer function's floor); elsewhere the "
              "coarser picture is interpolated. Turning it on or off installs the mask pieces (one "
              "compile each way).",
              low=0.0, unit="grey levels", pieces=True),
    Parameter("gaze_fixation_radius", "float", 0.02,
              "Gaze streams (PushGaze): how far the eye may wander from the rendered gaze, in viewport "
              "heights, before a frame re-renders (tracker jitter and microsaccades below it cause none).",
              low=0.0, unit="viewport heights"),
    Parameter("gaze_saccade_velocity", "float", 2.0,
              "Gaze streams: eye speed, in viewport heights per second, above which samples belong to a "
              "saccade; during one the last fixation is kept, and the landing moves the gaze at once.",
              low=0.0, unit="viewport heights per second"),
    Parameter("gaze_prediction", "float", 0.0,
              "Gaze streams: seconds to extrapolate a moving gaze (pursuit, drift) ahead to hide the "
              "render latency; 0 = off.", low=0.0, unit="seconds"),
    Parameter("progressive", "bool", False,
              "Progressive refinement: while camera, data, settings and gaze are still, each new frame "
              "widens the full-quality disc around the gaze until, after refinement_frames frames, the "
              "picture is the method at full quality; any change drops back to the foveated frame. An "
              "application renders the refining frames from a timer (NeedsRefinement)."),
    Parameter("refinement_frames", "int", 4,
              "Progressive refinement: still frames after the foveated one until full quality.",
              low=1, high=64),
) + SLAB

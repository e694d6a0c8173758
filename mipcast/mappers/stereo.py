"""Stereo pairs for every mipcast method through VTK's stereo render modes.

VTK renders a stereo frame as two passes, one per eye; every mipcast
mapper draws in both, so every method has stereo.  The eyes share the
camera's view transform; each eye's projection is sheared horizontally
(``vtkPerspectiveTransform::Stereo``) by ``tan(EyeAngle / 2)`` so that
points at the focal distance have no parallax, nearer points crossed
(left eye sees them further right) and farther ones uncrossed parallax.
VTK's ray caster starts each ray on the (sheared) bounding box but aims
it from the camera's mono position, which flattens the parallax of a
volume to a uniform shift; every mipcast mapper therefore installs the
``perspective_ray_direction`` piece (as for mono perspective frames), which
aims each ray along its pixel's line through the eye's sheared frustum: the
rays leave from the eye's centre of projection (:func:`eye_position`: the
shear is a lateral move of the camera by ``-s * tan(EyeAngle / 2) *
distance`` plus an off-axis frustum), and are well conditioned with the eye
inside the volume; a parallel camera's eyes get ``stereo_ray_direction``,
the eye's sheared direction (:func:`eye_uniforms`); mono parallel frames
VTK's code.  Everything else the mappers derive per frame
comes from the eye's own matrices, so each eye's image is that method seen
through that eye (tests/test_stereo.py checks it for every method against
a mono render through the eye's projection).

Modes (:data:`STEREO_MODES`):

- ``"anaglyph"``: red-cyan; the red channel from the left eye, green and
  blue from the right (VTK's ``AnaglyphColorMask`` 4, 3).
- ``"side-by-side"``: VTK's ``SplitViewportHorizontal``: left eye in the
  left half of the window, right eye in the right half, each squeezed to
  half width (the half side-by-side format 3D displays and headsets
  expand).
- ``"left"``, ``"right"``: one eye only (for checking the pair).
"""
from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np
from vtkmodules.vtkRenderingCore import vtkCamera

from mipcast.core.camera_rays import matrix_array
from mipcast.core.object_state import object_state
from mipcast.mappers.private_draw import rendering_renderer

#: Stereo mode name -> VTK's stereo type setter suffix.
STEREO_MODES = {"anaglyph": "Anaglyph", "side-by-side": "SplitViewportHorizontal",
                "left": "Left", "right": "Right"}
#: VTK's default angle between the eyes, degrees.
DEFAULT_EYE_ANGLE = 2.0


def set_stereo(render_window, mode: Optional[str], eye_angle: Optional[float] = None, camera=None) -> None:
    """Render ``render_window`` as a stereo pair (``mode`` of :data:`STEREO_MODES`), or mono (None/"off").

    Parameters
    ----------
    render_window : vtkRenderWindow
        Best set up before its first render (VTK asks for a stereo-capable
        window then; anaglyph and side-by-side work without one).
    mode : str or None
    eye_angle : float, optional
        Degrees between the eyes, set on ``camera``; default VTK's 2.
    camera : vtkCamera, optional
        The camera whose eye angle to set.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderWindow
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> window = vtkRenderWindow()
    >>> set_stereo(window, "anaglyph")
    >>> bool(window.GetStereoRender()), window.GetStereoTypeAsString()
    (True, 'Anaglyph')
    >>> set_stereo(window, None); bool(window.GetStereoRender())
    False
    >>> set_stereo(window, "3d")
    Traceback (most recent call last):
    ...
    ValueError: stereo mode '3d' is unknown; valid: 'anaglyph', 'side-by-side', 'left', 'right' (or None/'off')
    """
    if mode is None or mode == "off":
        render_window.StereoRenderOff()
        return
    if mode not in STEREO_MODES:
        raise ValueError(f"stereo mode {mode!r} is unknown; valid: "
                         f"{', '.join(map(repr, STEREO_MODES))} (or None/'off')")
    if eye_angle is not None:
        if not (isinstance(eye_angle, (int, float)) and 0.0 < float(eye_angle) < 90.0):
            raise ValueError(f"eye_angle must be a number of degrees in (0, 90), got {eye_angle!r}")
        if camera is None:
            raise ValueError("eye_angle needs the camera to set it on (camera=renderer.GetActiveCamera())")
        camera.SetEyeAngle(float(eye_angle))
    if not render_window.GetStereoCapableWindow() and render_window.GetNeverRendered():
        render_window.SetStereoCapableWindow(True)
    getattr(render_window, "SetStereoTypeTo" + STEREO_MODES[mode])()
    render_window.StereoRenderOn()


def eye_projection(camera, aspect: float, eye: str) -> np.ndarray:
    """The 4 x 4 projection VTK uses for one eye (``"left"``/``"right"``), depth range [-1, 1].

    The mono projection times the shear ``x += s * tan(EyeAngle / 2) * (z + distance)``
    in eye coordinates, ``s = +1`` for the left eye and ``-1`` for the right.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> camera = vtkCamera(); camera.SetPosition(0, 0, 10)
    >>> left, right = eye_projection(camera, 1.0, "left"), eye_projection(camera, 1.0, "right")
    >>> bool(np.isclose(left[0, 2], -right[0, 2])), bool(left[0, 2] > 0)
    (True, True)
    """
    if eye not in ("left", "right"):
        raise ValueError(f"eye must be 'left' or 'right', got {eye!r}")
    mono = matrix_array(camera.GetProjectionTransformMatrix(aspect, -1, 1))
    shear = np.eye(4)
    slope = math.tan(math.radians(camera.GetEyeAngle()) / 2.0) * (1.0 if eye == "left" else -1.0)
    shear[0, 2] = slope
    shear[0, 3] = slope * camera.GetDistance()
    return mono @ shear


def project(camera, aspect: float, eye: str, point: Sequence[float], size: Sequence[int]) -> tuple:
    """Pixel (x, y) of a world point in one eye's image of ``size`` (width, height), (0, 0) bottom-left.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> camera = vtkCamera(); camera.SetPosition(0, 0, 10)
    >>> [round(v, 3) for v in project(camera, 1.0, "left", camera.GetFocalPoint(), (64, 64))]
    [32.0, 32.0]
    """
    view = matrix_array(camera.GetViewTransformMatrix())
    clip = eye_projection(camera, aspect, eye) @ view @ np.array([*point, 1.0])
    ndc = clip[:3] / clip[3]
    return (float(0.5 * (ndc[0] + 1.0) * size[0]), float(0.5 * (ndc[1] + 1.0) * size[1]))


def predicted_disparity(camera, aspect: float, point: Sequence[float], size: Sequence[int]) -> float:
    """Horizontal parallax of a world point, right eye minus left eye, in pixels of an image of ``size``.

    Zero at the focal distance, negative (crossed) nearer, positive farther.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> camera = vtkCamera(); camera.SetPosition(0, 0, 10); camera.SetEyeAngle(4)
    >>> near, far = (predicted_disparity(camera, 1.0, (0, 0, z), (100, 100)) for z in (5, -5))
    >>> bool(near < 0 < far), abs(predicted_disparity(camera, 1.0, (0, 0, 0), (100, 100))) < 1e-9
    (True, True)
    """
    return project(camera, aspect, "right", point, size)[0] - project(camera, aspect, "left", point, size)[0]


def eye_position(camera, eye: str) -> np.ndarray:
    """World position of one eye's centre of projection under VTK's stereo shear.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> camera = vtkCamera(); camera.SetPosition(0, 0, 10); camera.SetEyeAngle(2 * 45.0)
    >>> eye_position(camera, "left").round(6).tolist()
    [-10.0, 0.0, 10.0]
    """
    slope = math.tan(math.radians(camera.GetEyeAngle()) / 2.0) * (1.0 if eye == "left" else -1.0)
    right = matrix_array(camera.GetViewTransformMatrix())[0, :3]
    return np.array(camera.GetPosition()) - slope * camera.GetDistance() * right


def drawing_camera(mapper, volume) -> Optional[vtkCamera]:
    """The camera ``mapper`` draws ``volume`` for now: ``object_state(mapper)["draw_camera"]`` (private
    level mappers drawing for another mapper), else the active camera of the renderer drawing ``volume``;
    None when neither is known.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> drawing_camera(None, vtkVolume()) is None
    True
    """
    camera = object_state(mapper).get("draw_camera") if mapper is not None else None
    if camera is None:
        renderer = rendering_renderer(mapper, volume)
        camera = renderer.GetActiveCamera() if renderer is not None else None
    return camera


def draw_for(mapper, camera: vtkCamera, renderer) -> None:
    """Before a private mapper draws for another (a brick, a foveated level, a rank's piece, DEMIP's first
    pass): the camera it draws with (:func:`drawing_camera`) and the multisampling of the window it draws
    for (:func:`drawing_multisamples`), which its own render target does not show.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkVolume
    >>> from mipcast.mappers.mip import MIPVolumeMapper
    >>> window, renderer, brick = vtkRenderWindow(), vtkRenderer(), MIPVolumeMapper()
    >>> window.AddRenderer(renderer); window.SetMultiSamples(4)
    >>> draw_for(brick, renderer.GetActiveCamera(), renderer)
    >>> drawing_multisamples(brick, vtkVolume())
    4
    """
    state = object_state(mapper)
    state["draw_camera"] = camera
    state["draw_multisamples"] = int(renderer.GetRenderWindow().GetMultiSamples())


def drawing_multisamples(mapper, volume) -> int:
    """The MSAA samples of the window ``mapper`` draws ``volume`` for (:func:`draw_for`'s, else the drawing
    renderer's window's; 0 when neither is known).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> drawing_multisamples(None, vtkVolume())
    0
    """
    samples = object_state(mapper).get("draw_multisamples") if mapper is not None else None
    if samples is None:
        renderer = rendering_renderer(mapper, volume)
        window = renderer.GetRenderWindow() if renderer is not None else None
        samples = window.GetMultiSamples() if window is not None else 0
    return int(samples)


def eye_uniforms(mapper, volume) -> Optional[dict]:
    """The ``stereo_ray_direction`` uniforms for the eye of a parallel stereo pair ``mapper`` renders now;
    None for mono frames and perspective eyes (``perspective_ray_direction`` aims those along their pixels'
    lines through the eye's sheared frustum).

    The camera is :func:`drawing_camera`'s.  Returns ``u_mc_eyeDirection`` (the eye's direction of
    projection, world).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> eye_uniforms(None, vtkVolume()) is None
    True
    """
    camera = drawing_camera(mapper, volume)
    if camera is None or not camera.GetStereo() or not camera.GetParallelProjection():
        return None
    eye = "left" if camera.GetLeftEye() else "right"
    slope = math.tan(math.radians(camera.GetEyeAngle()) / 2.0) * (1.0 if eye == "left" else -1.0)
    view = matrix_array(camera.GetViewTransformMatrix())
    # the parallel shear x += slope * z tilts the rays: along -z (forward) they move by +slope in x
    direction = -view[2, :3] + slope * view[0, :3]
    return {"u_mc_eyeDirection": [float(v) for v in direction / np.linalg.norm(direction)]}

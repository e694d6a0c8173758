"""Turntable (cine) projections: the volume turning about the screen's vertical axis.

MIP is read in motion: a single projection has no depth, a rotating one
shows which structure is in front.  :func:`turntable_frames` renders ``N``
frames of an :class:`mipcast.offscreen.OffscreenView`, the camera turned by
``360 / N`` degrees about the view-up axis through the focal point between
frames (the first frame is the view as set, so it equals ``mipcast render``
of the same view); :func:`write_animation` writes them as an animated GIF
(Pillow, which matplotlib already needs) or, where ``imageio`` with its
ffmpeg plugin is installed, as an MP4.

``mipcast render INPUT --turntable 36 --out spin.gif`` is the command line.

Examples
--------
>>> from mipcast.data_fixtures import make_fixture
>>> from mipcast.offscreen import OffscreenView
>>> frames = turntable_frames(OffscreenView(make_fixture("spheres", size=16), size=(24, 24)), 4,
...                           progress=False)
>>> len(frames), frames[0].shape
(4, (24, 24, 3))
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Callable, List, Sequence, Union

import numpy as np

#: Frames per second of the written animation (36 frames: a 3.6 s turn).
FPS = 10
#: Suffixes :func:`write_animation` writes.
SUFFIXES = (".gif", ".mp4")


def turntable_frames(view, frames: int, *, degrees: float = 360.0,
                     progress: Union[bool, Callable[[int, int], None], None] = None) -> List[np.ndarray]:
    """Render ``frames`` screenshots of ``view`` turning about its view-up axis.

    Parameters
    ----------
    view : mipcast.offscreen.OffscreenView
        The scene; its camera is turned and left where the last frame was.
    frames : int
        Number of frames, at least 2; frame ``k`` is turned by ``k * degrees / frames``.
    degrees : float, default: 360
        The whole turn (positive: the camera moves to the right, the volume
        seems to turn to the left).
    progress : bool or callable, optional
        ``None``/``True``: a tqdm bar on stderr when it is a terminal, else a
        plain line every tenth of the frames; ``False``: silent; a callable is
        called as ``progress(done, frames)`` after each frame.

    Returns
    -------
    list of numpy.ndarray
        (height, width, 3) uint8 frames, top row first.
    """
    if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 2:
        raise ValueError(f"a turntable needs at least 2 frames, got {frames!r}")
    frames = int(frames)
    step = float(degrees) / frames
    report, close = _reporter(progress, frames)
    pictures = []
    try:
        for index in range(frames):
            if index:
                view.camera.Azimuth(step)
                view.camera.OrthogonalizeViewUp()
                view.renderer.ResetCameraClippingRange()
            pictures.append(view.screenshot())
            report(index + 1, frames)
    finally:
        close()
    return pictures


def write_animation(path: Union[str, Path], frames: Sequence[np.ndarray], fps: float = FPS) -> Path:
    """Write ``frames`` as an endlessly looping GIF, or an MP4 (needs ``imageio[ffmpeg]``).

    Grey frames (R = G = B, the MIP methods) go into the GIF exactly (a grey
    palette); coloured ones (DEMIP's colour sphere) are quantised to 256
    colours per frame.

    Raises
    ------
    ValueError
        For a suffix other than ``.gif``/``.mp4``, or ``.mp4`` without imageio's ffmpeg plugin.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> path = os.path.join(tempfile.mkdtemp(), "spin.gif")
    >>> frames = [np.full((8, 8, 3), v, np.uint8) for v in (0, 128, 255)]
    >>> from PIL import Image
    >>> Image.open(write_animation(path, frames)).n_frames
    3
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in SUFFIXES:
        raise ValueError(f"a turntable is written as {' or '.join(SUFFIXES)}, got {path.name!r}")
    path.parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".mp4":
        try:
            import imageio.v2 as imageio
            imageio.mimwrite(path, list(frames), fps=fps, macro_block_size=1)
        except ImportError as error:
            raise ValueError(f"writing .mp4 needs imageio with ffmpeg (pip install 'imageio[ffmpeg]'); "
                             f"write a .gif instead ({error})") from None
        return path
    from PIL import Image

    pictures = []
    for frame in frames:
        frame = np.ascontiguousarray(frame[..., :3])
        if np.array_equal(frame[..., 0], frame[..., 1]) and np.array_equal(frame[..., 0], frame[..., 2]):
            pictures.append(Image.fromarray(frame[..., 0], mode="L"))
        else:
            pictures.append(Image.fromarray(frame, mode="RGB").quantize(256, method=Image.Quantize.MEDIANCUT))
    pictures[0].save(path, save_all=True, append_images=pictures[1:], duration=round(1000.0 / fps),
                     loop=0, optimize=False, disposal=1)
    return path


def write_turntable(view, frames: int, path: Union[str, Path], fps: float = FPS) -> Path:
    """:func:`turntable_frames` then :func:`write_animation` (the suffix is checked first)."""
    _check_suffix(path, "--turntable")
    return write_animation(path, turntable_frames(view, frames), fps=fps)


def _check_suffix(path, option: str) -> None:
    """Refuse an ``--out`` that is no animation file (before any frame renders)."""
    if Path(path).suffix.lower() not in SUFFIXES:
        raise ValueError(f"{option} writes an animation: --out must end in {' or '.join(SUFFIXES)}, "
                         f"got {Path(path).name!r}")


def _reporter(progress, total: int):
    """(report(done, total), close()) for the ``progress`` argument of :func:`turntable_frames`."""
    if progress is False:
        return (lambda done, total: None), (lambda: None)
    if callable(progress) and progress is not True:
        return progress, (lambda: None)
    if sys.stderr is not None and sys.stderr.isatty():
        from tqdm import tqdm

        bar = tqdm(total=total, unit="frame", desc="turntable", dynamic_ncols=True)
        return (lambda done, total: bar.update(1)), bar.close
    every = max(1, total // 10)

    def line(done: int, total: int) -> None:
        if done % every == 0 or done == total:
            print(f"turntable: frame {done}/{total}", file=sys.stderr, flush=True)

    return line, (lambda: None)


def slab_sweep_frames(view, frames: int, *, progress: Union[bool, Callable[[int, int], None]] = True
                      ) -> List[np.ndarray]:
    """``frames`` pictures of the view's slab moving through the volume, front to back.

    The slab (``SetSlabThickness``, > 0) keeps its thickness and normal (the
    view direction unless ``SetSlabNormal`` set one); its centre moves along
    the normal from where the slab's front face touches the volume's near
    corner to where its back face touches the far one (the middle, if the
    slab is thicker than the volume).  The camera does not move; the slab
    centre is put back afterwards.  Moving the slab uploads uniforms only.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> from mipcast.offscreen import OffscreenView
    >>> view = OffscreenView(make_fixture("frontback", size=16), "analytic", size=(24, 24), view="front")
    >>> view.mapper.SetSlabThickness(4.0)
    >>> frames = slab_sweep_frames(view, 3, progress=False)
    >>> len(frames), bool((frames[0] != frames[2]).any())
    (3, True)
    """
    if isinstance(frames, bool) or not isinstance(frames, int) or frames < 2:
        raise ValueError(f"--slab-sweep needs at least 2 frames, got {frames!r}")
    mapper = view.mapper
    thickness = mapper.GetSlabThickness() if hasattr(mapper, "GetSlabThickness") else 0.0
    if not thickness:
        raise ValueError("--slab-sweep needs --slab THICKNESS (a slab to move through the volume), "
                         "with a mipcast method (not stock or cpu)")
    camera = view.camera
    normal = np.array(mapper.GetSlabNormal() or camera.GetDirectionOfProjection(), float)
    normal /= np.linalg.norm(normal)
    saved = mapper.GetSlabCentre()
    start = np.array(saved or camera.GetFocalPoint(), float)
    bounds = view.volume.GetBounds()
    corners = np.array([[x, y, z] for x in bounds[0:2] for y in bounds[2:4] for z in bounds[4:6]])
    along = corners @ normal
    first, last = along.min() + 0.5 * thickness, along.max() - 0.5 * thickness
    if last < first:
        first = last = 0.5 * (along.min() + along.max())
    report, close = _reporter(progress, frames)
    pictures = []
    try:
        for index, where in enumerate(np.linspace(first, last, frames)):
            mapper.SetSlabCentre(*(start + (where - start @ normal) * normal))
            pictures.append(view.screenshot())
            report(index + 1, frames)
    finally:
        mapper.SetSlabCentre(saved)
        close()
    return pictures


def write_slab_sweep(view, frames: int, path: Union[str, Path], fps: float = FPS) -> Path:
    """:func:`slab_sweep_frames` then :func:`write_animation` (the suffix is checked first)."""
    _check_suffix(path, "--slab-sweep")
    return write_animation(path, slab_sweep_frames(view, frames), fps=fps)

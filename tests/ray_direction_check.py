"""Perspective rays with and without ``shaders/perspective_ray_direction.glsl``: error and time.

    python tests/ray_direction_check.py errors [CASE ...]   # differential cases, eye inside the volume
    python tests/ray_direction_check.py time [ROUNDS]        # vessels 96^3, 512^2 perspective, mip and analytic

``errors``: each case of ``tests/differential_check.py`` (default: the eye-inside cases 109 148 231 234 274
275 396 543 575) drawn with VTK's own ray direction and with the piece, the float readout's largest error
against the float64 reference on the same rays, in fractions of the range.  ``time``: median frame ms of
both, interleaved in one process after a warm-up frame, auto-adjust off, and their ratio (llvmpipe: the
ratio is what means something).  Figures in docs/reliability.md, "The eye inside the volume".
"""
import random
import statistics
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

import differential_check as dc
import mipcast.mappers.mip as mip
from mipcast.data_fixtures import make_fixture
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView

EYE_INSIDE = (109, 148, 231, 234, 274, 275, 396, 543, 575)
_WITH = mip.MIPVolumeMapper._pieces_now


def piece_switch(piece: str):
    """``use(on)``: every mipcast mapper draws with its own pieces from now on (True) or with them less
    ``piece`` (False)."""
    def without(self, volume) -> tuple:
        return tuple(name for name in _WITH(self, volume) if name != piece)

    def use(on: bool) -> None:
        mip.MIPVolumeMapper._pieces_now = _WITH if on else without
    return use


#: Perspective rays with the piece (True) or along VTK's own direction (False) from now on.
use_piece = piece_switch(mip.PERSPECTIVE_PIECE)


def case_error(number: int, base: np.ndarray) -> tuple:
    """(method, largest float-readout error of the range) of differential case ``number`` (foveated: its fovea
    is not separated here, so such cases are skipped: None)."""
    case = dc.draw_case(random.Random(number))
    if case["method"] == "foveated":
        return case["method"], None
    image, reference_image, mask = dc.volumes(case, base)
    scene = dc.scene_for(case, image, reference_image)
    planes, cropping, matrix, settings = dc.configure(scene, case, number, image, mask)
    got = scene.float_image()
    component = dc.case_settings(case)[0]
    clip = (np.concatenate([p[0] for p in planes]), np.concatenate([p[1] for p in planes])) if planes else None
    if dc.nearest_case(case, number):
        settings["interpolation"] = "nearest"
    expected = METHODS[case["method"]].reference(
        reference_image, scene.camera, scene.size, sample_distance=scene.sample_distance, window=scene.window,
        clip_planes=clip, cropping=cropping, matrix=matrix, **settings,
        **({"component": component} if component is not None else {}))
    values = dc.drawn_values(reference_image, component)
    both = np.isfinite(got) & np.isfinite(expected)
    return case["method"], float(np.abs(got[both] - expected[both]).max() / (np.nanmax(values) - np.nanmin(values)))


def errors(numbers) -> None:
    base = vtk_to_numpy(make_fixture("vessels", size=24).GetPointData().GetScalars()).astype(np.float64)
    base = base.reshape(24, 24, 24)
    for number in numbers:
        found = {}
        for on in (False, True):
            use_piece(on)
            method, found[on] = case_error(number, base)
        use_piece(True)
        if found[True] is not None:
            print(f"case {number} ({method}): VTK's direction {found[False]:.2e}, the piece {found[True]:.2e}")


def piece_medians(image, method: str, view: str, use, rounds: int) -> tuple:
    """Median frame ms (without, with) a piece: one 512^2 view per setting (``use(on)`` switches the piece
    before each is made and drawn, auto-adjust off), frames interleaved, the first round a warm-up."""
    views = {}
    for on in (False, True):
        use(on)
        views[on] = OffscreenView(image, method, size=(512, 512), view=view)
        views[on].mapper.SetAutoAdjustSampleDistances(False)
    times = {False: [], True: []}
    for index in range(rounds):
        for on, scene in views.items():
            use(on)
            frame = scene.frame_times(frames=1, warmup=1 if index == 0 else 0)[0]
            if index:
                times[on].append(frame)
    use(True)
    return tuple(1000.0 * statistics.median(times[on]) for on in (False, True))


def timing(rounds: int = 9) -> None:
    image = make_fixture("vessels", size=96)
    for method in ("mip", "analytic"):
        vtk, piece = piece_medians(image, method, "perspective", use_piece, rounds)
        print(f"{method}: VTK's direction {vtk:.1f} ms, the piece {piece:.1f} ms, ratio {piece / vtk:.3f}")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "time":
        timing(int(sys.argv[2]) if len(sys.argv) > 2 else 9)
    elif len(sys.argv) > 1 and sys.argv[1] == "errors":
        errors([int(n) for n in sys.argv[2:]] or EYE_INSIDE)
    else:
        sys.exit(__doc__)

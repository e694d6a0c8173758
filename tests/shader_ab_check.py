"""Frame time of two shader folders on the SAME view objects: the cost of a shader change on llvmpipe.

    git archive REV shaders | tar -x -C /tmp/before     # the folder as it was at REV (/tmp/before/shaders)
    python tests/shader_ab_check.py /tmp/before/shaders shaders [ROUNDS]

Vessels 96^3, 512^2, mip and analytic in the front, oblique and perspective views, auto-adjust off. Each
view object draws with folder A and folder B in turn (the pieces reinstalled at each switch, three frames
untimed, then two timed; VTK's shader cache keeps both programs), rounds alternating which goes first; it
prints the medians and B/A.  Views made anew differ by +-10 % between identical shaders (their textures
land elsewhere), so only the same objects tell a few per cent; A against a copy of itself gives 0.998-0.999,
and a change of shader text that adds no work moves a case by up to 4 % (llvmpipe's code layout).  Figures:
docs/reliability.md, "A face seen edge-on".
"""
import statistics
import sys
from pathlib import Path

import mipcast.mappers.shader_pieces as shader_pieces
from mipcast.core.object_state import object_state
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

CASES = [(view, method) for view in ("front", "oblique", "perspective") for method in ("mip", "analytic")]


def main(folder_a: str, folder_b: str, rounds: int = 11) -> None:
    folder = {"now": folder_a}
    shader_pieces._read_piece_text = lambda name: (Path(folder["now"]) / f"{name}.glsl").read_text()

    def use(which: str, scene) -> None:
        folder["now"] = folder_a if which == "A" else folder_b
        shader_pieces.load_piece.cache_clear()
        object_state(scene.mapper).pop("installed", None)  # reinstalled from that folder at the next render
        scene.frame_times(frames=3, warmup=0)
        assert object_state(scene.mapper).get("installed"), "the pieces were not reinstalled"

    image = make_fixture("vessels", size=96)
    scenes = {}
    for view, method in CASES:
        scene = OffscreenView(image, method, size=(512, 512), view=view)
        scene.mapper.SetAutoAdjustSampleDistances(False)
        use("A", scene)
        use("B", scene)
        scenes[(view, method)] = scene
    times = {(which, case): [] for which in "AB" for case in CASES}
    for index in range(rounds):
        for case in CASES:
            for which in ("A", "B") if index % 2 == 0 else ("B", "A"):
                use(which, scenes[case])
                times[(which, case)] += scenes[case].frame_times(frames=2, warmup=0)
    for case in CASES:
        a, b = (1000.0 * statistics.median(times[(which, case)]) for which in "AB")
        print(f"{case[0]} {case[1]}: A {a:.1f} ms, B {b:.1f} ms, B/A {b / a:.3f}")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 11)

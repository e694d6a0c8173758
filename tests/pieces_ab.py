"""Frame time of the current shader pieces against the same pieces at another git revision, in one process.

    python tests/pieces_ab.py REV SCENE SIZE METHODS [--pieces NAME ...] [--rounds 9]
    e.g. python tests/pieces_ab.py 5346ec2 vessels@0.25,1 512 mip,analytic,demip

Each method is drawn twice (``OffscreenView``, oblique): with the installed pieces and with the pieces
named by ``--pieces`` as they were at REV (read with ``git show``, loaded under ``<name>_old``); medians of
interleaved rounds of 3 frames after a warm-up, and whether the two pictures are identical.  The Python
around the pieces is today's in both, so this times a shader change alone (docs/methods.md, "Block
skipping": the missing-value hooks).
"""
import argparse
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import mipcast.mappers.mip as mip_module
from mipcast.app.cli import _load_scene
from mipcast.mappers import shader_pieces
from mipcast.offscreen import OffscreenView

HOOKS = ("mip_hooks_blocks", "minip_hooks_blocks", "demip_hooks_blocks", "amip_max_hooks", "amip_min_hooks")


def old_pieces(revision: str, names) -> dict:
    """``{name: name + "_old"}``, the pieces at ``revision`` written to a folder the loader searches."""
    folder = Path(tempfile.mkdtemp())
    root = Path(__file__).resolve().parent.parent
    for name in names:
        text = subprocess.run(["git", "show", f"{revision}:shaders/{name}.glsl"], cwd=root, check=True,
                              capture_output=True, text=True).stdout
        (folder / f"{name}_old.glsl").write_text(text.replace(f"// mipcast piece: {name}\n",
                                                              f"// mipcast piece: {name}_old\n", 1))
    shader_pieces.register_folder(folder)
    # the old sampled block hooks still get the skipping uniforms
    mip_module._BLOCK_PIECES = mip_module._BLOCK_PIECES | {f"{n}_old" for n in names if n in mip_module._BLOCK_PIECES}
    return {name: f"{name}_old" for name in names}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("revision")
    parser.add_argument("scene", help="NAME[@LOW,HIGH], as mipcast bench --scenes")
    parser.add_argument("size", type=int)
    parser.add_argument("methods")
    parser.add_argument("--pieces", nargs="+", default=list(HOOKS))
    parser.add_argument("--rounds", type=int, default=9)
    args = parser.parse_args()
    swap = old_pieces(args.revision, args.pieces)
    image, window = _load_scene(args.scene, 128)
    views = {}
    for method in args.methods.split(","):
        for tag in ("now", "old"):
            view = OffscreenView(image, method, size=(args.size, args.size), window=window)
            if tag == "old":
                current = view.mapper.GetShaderPieces
                view.mapper.GetShaderPieces = lambda current=current: tuple(swap.get(n, n) for n in current())
            views[method, tag] = view
    pictures = {key: view.screenshot() for key, view in views.items()}
    times = {key: [] for key in views}
    for _ in range(args.rounds):
        for key, view in views.items():
            view.render_window.Render()
            start = time.perf_counter()
            for _ in range(3):
                view.render_window.Render()
            times[key].append((time.perf_counter() - start) / 3)
    for method in args.methods.split(","):
        now, old = statistics.median(times[method, "now"]), statistics.median(times[method, "old"])
        same = np.array_equal(pictures[method, "now"], pictures[method, "old"])
        print(f"{args.scene} {args.size}^2 {method}: now {1e3 * now:.1f} ms, at {args.revision} {1e3 * old:.1f} ms, "
              f"now/old {now / old:.3f}, pictures identical: {same}")


if __name__ == "__main__":
    main()

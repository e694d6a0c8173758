"""Hashes of every method's pictures, to prove a refactor changed no pixel.

Renders each method (and each projection/cue/setting variant) x fixture x
view (orthographic and perspective), as the 8-bit screenshot and, where the
method has one, the float readout, and prints one JSON object
``{case: sha256}``.  Run it before and after a change and compare:

    python3 tests/picture_hashes.py > before.json
    ... change ...
    python3 tests/picture_hashes.py > after.json
    python3 tests/picture_hashes.py --compare before.json after.json

Hashes depend on the renderer (Mesa version, GPU driver): compare runs made
on one machine only.  ``docs/refactor-hashes.json`` holds the run made on
the development machine (llvmpipe) before the "one definition per method"
restructuring; its 46 foveated entries were made again when the foveation
plan's ``start`` began keeping every coarse level out of the fovea (at these
64 x 56 views the full-quality disc grew; every other entry unchanged), and
its 8-bit entries were made again (125 changed, no float entry) when the
colour pieces began reading VTK's tables where they hold the value
(docs/methods.md, "Reading VTK's tables where they hold the value"), and its
perspective entries (63 float, 1 8-bit) when mono perspective rays began
aiming along the pixel's line through the frustum
(shaders/perspective_ray_direction.glsl: floats within 4.4e-6 of the
range of their old values, 3 pixels of one 8-bit picture 1 grey apart).
"""
from __future__ import annotations

import hashlib
import json
import sys

import numpy as np

#: (label, method, parameters) - every method of the table plus the variants
#: whose shader pieces differ.
VARIANTS = [
    ("stock", "stock", {}),
    ("cpu", "cpu", {}),
    ("mip", "mip", {}),
    ("analytic", "analytic", {}),
    ("analytic-unpacked", "analytic", {"packed_corners": False}),
    ("analytic-noskip", "analytic", {"skipping": False}),
    ("demip", "demip", {}),
    ("demip-w0", "demip", {"depth_weight": 0.0}),
    ("demip-window", "demip", {"depth_mode": "window", "depth_weight": 0.4}),
    ("demip-steps", "demip", {"depth_mode": "steps", "depth_weight": 0.4}),
    ("demip-eye", "demip", {"depth_mode": "eye_distance", "depth_weight": 0.4}),
    ("demip-sphere", "demip", {"sphere_weight": 0.5, "sphere_colors": "green-red"}),
    ("demip-chroma", "demip", {"chroma_depth_weight": 0.5}),
    ("demip-chroma-max", "demip", {"chroma_depth_weight": 0.5, "depth_of": "maximum", "depth_weight": 0.0}),
    ("demip-lmip", "demip", {"projection": "lmip"}),
    ("demip-attenuated", "demip", {"projection": "attenuated"}),
    ("demip-mida", "demip", {"projection": "mida"}),
    ("demip_two_pass", "demip_two_pass", {}),
    ("demip_two_pass-sphere", "demip_two_pass", {"sphere_weight": 0.5, "depth_mode": "window"}),
    ("foveated", "foveated", {}),
    ("foveated-corner", "foveated", {"gaze_point": (0.1, 0.1)}),
    ("foveated-analytic", "foveated", {"method": "analytic", "gaze_point": (0.3, 0.6)}),
    ("foveated-demip", "foveated", {"method": "demip", "gaze_point": (0.7, 0.4)}),
]
FIXTURES = ("vessels", "noise", "frontback")
VIEWS = ("oblique", "perspective")
SIZE = (64, 56)


def _digest(array: np.ndarray) -> str:
    return hashlib.sha256(np.ascontiguousarray(array).tobytes()).hexdigest()[:16]


def picture_hashes() -> dict:
    from mipcast.data_fixtures import make_fixture
    from mipcast.offscreen import OffscreenView
    from mipcast.core.parameters import set_parameters

    hashes = {}
    for fixture in FIXTURES:
        image = make_fixture(fixture, size=32)
        for label, method, params in VARIANTS:
            for view_name in VIEWS:
                view = OffscreenView(image, method, size=SIZE, view=view_name, window="full")
                set_parameters(view.mapper, **params)
                key = f"{fixture}/{label}/{view_name}"
                hashes[key + "/8bit"] = _digest(view.screenshot())
                if method not in ("stock", "cpu"):
                    hashes[key + "/float"] = _digest(view.float_image().astype(np.float32))
                view.render_window.Finalize()
    return hashes


def compare(before_path: str, after_path: str) -> int:
    with open(before_path) as f:
        before = json.load(f)
    with open(after_path) as f:
        after = json.load(f)
    changed = sorted(k for k in before if k in after and before[k] != after[k])
    missing = sorted(set(before) - set(after))
    print(f"{len(before)} hashes before, {len(after)} after: {len(changed)} changed, {len(missing)} missing")
    for key in changed + missing:
        print("  ", key, before.get(key), after.get(key))
    return 1 if changed or missing else 0


if __name__ == "__main__":
    if sys.argv[1:2] == ["--compare"]:
        sys.exit(compare(sys.argv[2], sys.argv[3]))
    json.dump(picture_hashes(), sys.stdout, indent=1, sort_keys=True)
    print()

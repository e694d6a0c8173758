"""ParaView draws a volume beyond the 3D texture limit in bricks (the mapper's own bricking).

Usage (from the repository root)::

    PYTHONPATH=$(python3 tests/installed.py):tests xvfb-run -a pvpython tests/paraview_bricks_check.py [--plugin SO]

The "vessels" fixture (48^3) is shown in a render view with the limit lowered to 20 points
per axis (``gpu_limits.max_texture_size_3d``, so 3 x 3 x 3 bricks) and without it, through
:func:`mipcast.plugin.render_view.show` and, with ``--plugin``, the "mipcast" representation;
analytic MIP and foveated (its levels composited over bricks before blending,
mipcast.mappers.bricked_foveated) must draw the same picture (within one grey level), with no
refusal in ParaView's messages.  Prints one JSON object on the last line; used by
tests/test_bricked_mapper.py.
"""
import argparse
import inspect
import json
import os
import tempfile

import numpy as np

from mipcast.data_fixtures import make_fixture
from mipcast.mappers import gpu_limits

LIMIT = 20


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin")
    args = parser.parse_args()
    if not hasattr(inspect, "getargspec"):  # ParaView 5.11's plugin loader on Python 3.11
        inspect.getargspec = inspect.getfullargspec
    import paraview_representation_check as check
    from paraview.simple import Delete, LoadPlugin, OpenDataFile
    from mipcast.plugin.render_view import show

    routes = ["render_view"]
    if args.plugin:
        LoadPlugin(args.plugin, remote=False, ns=globals())
        routes.append("representation")
    directory = tempfile.mkdtemp(prefix="mipcast-pvbricks-")
    path = os.path.join(directory, "vessels.vti")
    check.write_vti(make_fixture("vessels", size=48), path)
    real = gpu_limits.max_texture_size_3d
    report = {}
    for route in routes:
        for method in ("analytic", "foveated"):
            pictures, messages = [], []
            for limit in (None, LIMIT):
                gpu_limits.max_texture_size_3d = real if limit is None else (lambda window: LIMIT)
                try:
                    reader = OpenDataFile(path)
                    reader.PointArrayStatus = [check.ARRAY]
                    # the screenshot's size: no tiles (a tiled foveated frame beyond the texture limit keeps
                    # each tile's own coarse levels, with seams: plugin/README.md, Limits)
                    view = check.plain_view((check.WIDTH, check.HEIGHT))
                    with check.Messages() as captured:
                        if route == "representation":
                            check.show_mipcast(reader, view, method)
                        else:
                            show(reader, view, method, check.ARRAY)
                        check.set_camera(view)
                        name = f"{route}-{method}-{limit or 'one'}"
                        pictures.append(check.screenshot(view, os.path.join(directory, name + ".png")).astype(int))
                        messages.append(captured.text())
                    Delete(view)
                    Delete(reader)
                finally:
                    gpu_limits.max_texture_size_3d = real
            difference = np.abs(pictures[0] - pictures[1]).max(axis=-1)
            report[f"{route} {method}"] = {
                "max_one": int(pictures[0].max()), "max_bricked": int(pictures[1].max()),
                "within_1": float(np.mean(difference <= 1)),
                "refused": f"3D texture limit of {LIMIT}" in messages[1],
                "messages_one": messages[0][-300:]}
    print(json.dumps(report))


if __name__ == "__main__":
    main()

"""Soak: many frames changing camera, method, parameters, grey window, window size and input.

Usage::

    python tests/soak.py --frames 10000 [--size 64] [--json out.json]

Each frame makes one kind of change (round robin: camera, parameter, window,
input, size, method; a parameter change on a method without uniform-only
parameters becomes a camera change), renders, and records:

* RSS (``/proc/self/status`` VmRSS, after ``gc.collect()``) at the start,
  after warm-up (the first fifth of the frames, at most 1000) and at the end;
* shader compiles and program switches, read from VTK: after each render,
  the program the window's shader cache bound last
  (``vtkOpenGLShaderCache.GetLastShaderBound()``, the volume's ray-cast
  program) is compared with every program seen so far (a *compile*: a
  program never bound before; the cache keeps every program until the window
  goes, so a new one is a real compile) and with the program this method was
  drawn with the last time it was drawn (a *switch*: another program was
  bound for the same method; after a method change, the one it had before).
  A rebuild of the shader source that hashes to the program already bound is
  not visible this way (VTK does not expose it); it costs CPU time, no compile.

Printed as JSON; docs/reliability.md, section "Soak", holds a 10,000-frame run.
"""
from __future__ import annotations

import argparse
import gc
import json
import sys
import time

import numpy as np

KINDS = ("camera", "parameter", "window", "input", "size", "method")


def rss_bytes() -> int:
    """Resident set size of this process in bytes (Linux), after a garbage collection."""
    gc.collect()
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


def _uniform_parameters(method):
    """The method's numeric parameters that install no other pieces (uniforms, or CPU-side plans)."""
    return [p for p in method.parameters if not p.pieces and p.kind in ("float", "int")]


def _random_value(parameter, rng):
    low = 0.0 if parameter.low is None else float(parameter.low)
    high = low + 1.0 if parameter.high is None else float(parameter.high)
    if parameter.kind == "int":
        return int(rng.integers(int(low), int(high) + 1))
    value = float(rng.uniform(low, high))
    return max(value, low + 1e-3 * (high - low)) if parameter.open_low else value


def run(frames: int = 500, size: int = 64, seed: int = 0, warmup=None) -> dict:
    """Render ``frames`` frames with changes; return the figures (see the module docstring)."""
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkVolume
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

    from mipcast import methods
    from mipcast.data_fixtures import make_fixture
    from mipcast.offscreen import grey_property, set_view

    rng = np.random.default_rng(seed)
    warmup = min(max(frames // 5, 1), 1000) if warmup is None else int(warmup)
    shape = 24
    images = [make_fixture(name, size=shape) for name in ("vessels", "spheres", "noise")]
    images.append(make_fixture("vessels", size=shape + 8))  # a second shape
    low, high = images[0].GetPointData().GetScalars().GetRange(0)
    names = [name for name in methods.METHODS]
    mappers = {}
    for name in names:
        mapper = methods.create_mapper(name)
        mapper.SetInputData(images[0])
        mapper.SetAutoAdjustSampleDistances(False)
        mapper.SetSampleDistance(1.0)
        mappers[name] = mapper
    volume = vtkVolume()
    volume.SetProperty(grey_property((low + 0.2 * (high - low), high)))
    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(True)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    window.SetSize(size, size)
    current = names[0]
    methods.attach(mappers[current], volume)
    set_view(renderer, images[0], "oblique")
    cache = window.GetShaderCache()

    seen, last_program = set(), {}
    counts = {kind: {"frames": 0, "compiles": 0, "switches": 0} for kind in KINDS}
    warm_compiles = 0
    rss = {"start": rss_bytes()}
    method_order = list(names)
    image_index = {name: 0 for name in names}
    trace, trace_every = [], max(frames // 20, 1)
    start = time.perf_counter()
    measured_start = start
    for frame in range(frames):
        if frame % trace_every == 0:
            trace.append(round(rss_bytes() / 2 ** 20, 1))
        if frame == warmup:
            rss["after_warmup"] = rss_bytes()
            measured_start = time.perf_counter()
        kind = KINDS[frame % len(KINDS)]
        method = methods.METHODS[current]
        if kind == "parameter" and not _uniform_parameters(method):
            kind = "camera"
        mapper = mappers[current]
        if kind == "camera":
            camera = renderer.GetActiveCamera()
            camera.Azimuth(float(rng.uniform(-20, 20)))
            camera.Elevation(float(rng.uniform(-10, 10)))
            camera.OrthogonalizeViewUp()
            camera.SetParallelScale(camera.GetParallelScale() * float(rng.uniform(0.95, 1.05)))
        elif kind == "parameter":
            parameter = _uniform_parameters(method)[int(rng.integers(len(_uniform_parameters(method))))]
            getattr(mapper, parameter.setter)(_random_value(parameter, rng))
        elif kind == "window":
            # stays above the data minimum (a transfer-function floor): analytic MIP keeps its loop variant
            lo = low + float(rng.uniform(0.05, 0.4)) * (high - low)
            hi = lo + float(rng.uniform(0.2, 1.0)) * (high - lo)
            colour, opacity = volume.GetProperty().GetRGBTransferFunction(0), volume.GetProperty().GetScalarOpacity(0)
            colour.RemoveAllPoints()
            colour.AddRGBPoint(lo, 0.0, 0.0, 0.0)
            colour.AddRGBPoint(hi, 1.0, 1.0, 1.0)
            opacity.RemoveAllPoints()
            opacity.AddPoint(lo, 1.0)
            opacity.AddPoint(hi, 1.0)
        elif kind == "input":
            image_index[current] = (image_index[current] + 1) % len(images)
            mapper.SetInputData(images[image_index[current]])
        elif kind == "size":
            side = int(size + rng.integers(-8, 9))
            window.SetSize(side, side)
        else:  # method
            current = method_order[(method_order.index(current) + 1) % len(method_order)]
            methods.attach(mappers[current], volume)
        window.Render()
        program = cache.GetLastShaderBound()
        address = program.GetAddressAsString("vtkObjectBase") if program is not None else None
        compiled = address not in seen
        switched = current in last_program and last_program[current] != address
        seen.add(address)
        last_program[current] = address
        if frame < warmup:
            warm_compiles += compiled
            continue
        counts[kind]["frames"] += 1
        counts[kind]["compiles"] += int(compiled)
        counts[kind]["switches"] += int(switched)
    end = time.perf_counter()
    rss["end"] = rss_bytes()
    rss.setdefault("after_warmup", rss["end"])
    measured = frames - warmup
    return {
        "frames": frames, "warmup_frames": warmup, "image_size": size, "methods": names,
        "rss_mb": {k: round(v / 2 ** 20, 2) for k, v in rss.items()},
        "rss_growth_mb": round((rss["end"] - rss["after_warmup"]) / 2 ** 20, 2),
        "compiles_in_warmup": warm_compiles, "programs": len(seen),
        "after_warmup": counts,
        "rss_trace_mb": trace, "rss_trace_every": trace_every,
        "frames_per_second": round(measured / (end - measured_start), 1) if measured > 0 else None,
        "seconds": round(end - start, 1),
        "renderer": window.ReportCapabilities().split("OpenGL renderer string:")[-1].split("\n")[0].strip(),
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--frames", type=int, default=10000)
    parser.add_argument("--size", type=int, default=64, help="window side in pixels (changes by +-8)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", help="also write the figures to this file")
    args = parser.parse_args(argv)
    figures = run(args.frames, args.size, args.seed)
    text = json.dumps(figures, indent=2)
    print(text)
    if args.json:
        with open(args.json, "w") as out:
            out.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

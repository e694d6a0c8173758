"""Fuzz mipcast.io.dicom.read_dicom with mutated real and generated DICOM files.

Each case mutates one seed file (pydicom's test files of several transfer
syntaxes, plus a generated Siemens mosaic and an enhanced multi-frame) by
truncation, bit flips, wrong element lengths, wrong VRs, spliced bytes or a
lying header (Rows, Columns, NumberOfFrames, BitsAllocated, SamplesPerPixel
far beyond the stored pixel data), writes it to a file and reads it.  A case
fails if the reader raises anything but :class:`mipcast.io.dicom.DicomError`
(a ValueError), takes longer than 5 s, or allocates more than
``MEMORY_BOUND`` (traced by tracemalloc, which numpy reports to).

Usage (from the repository root)::

    PYTHONPATH=$PWD python3 tests/dicom_fuzz.py --cases 10000 [--seed 0]

prints the figures (cases, outcomes by class, slowest case, peak memory)
and exits with 1 if any case failed.  tests/test_dicom_fuzz.py runs a few
hundred cases through hypothesis.
"""
import argparse
import collections
import io
import os
import random
import resource
import signal
import struct
import sys
import tempfile
import time
import tracemalloc
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

TIME_LIMIT_S = 5.0
MEMORY_BOUND = 256 * 2 ** 20   # bytes traced per case; the lying headers ask for up to TiBs
SEED_NAMES = ("CT_small.dcm", "MR_small.dcm", "MR_small_RLE.dcm", "MR_small_jp2klossless.dcm",
              "MR_small_jpeg_ls_lossless.dcm", "rtdose.dcm", "emri_small_RLE.dcm",
              "JPGLosslessP14SV1_1s_1f_8b.dcm", "JPEGLSNearLossless_16.dcm")
KINDS = ("truncate", "bitflip", "length", "vr", "splice", "lying")
VRS = [b"AE", b"AS", b"AT", b"CS", b"DA", b"DS", b"DT", b"FD", b"FL", b"IS", b"LO", b"LT", b"OB",
       b"OD", b"OF", b"OL", b"OW", b"PN", b"SH", b"SL", b"SQ", b"SS", b"ST", b"TM", b"UI", b"UL",
       b"UN", b"US", b"UT", b"ZZ"]
LONG_VRS = {b"OB", b"OD", b"OF", b"OL", b"OW", b"SQ", b"UN", b"UT"}
LENGTHS = (0, 1, 2, 3, 0xFFFF, 0x7FFFFFFF, 0xFFFFFFFE, 0xFFFFFFFF)
LIES = {"Rows": (0, 1, 3, 1000, 65535), "Columns": (0, 1, 7, 4096, 65535),
        "NumberOfFrames": ("0", "2", "1000", "999999", "-1", "x"),
        "BitsAllocated": (0, 1, 12, 32, 64), "SamplesPerPixel": (0, 3, 4),
        "PixelRepresentation": (1, 7), "BitsStored": (0, 33)}


#: For DicomError outcomes: the class of the error it wraps (``__cause__``), or "-" if none.
CAUSES = collections.Counter()


class Hang(BaseException):  # not an Exception: the reader must not catch it
    pass


def seeds():
    """[(name, bytes)]: pydicom's test files found here, and generated ones."""
    from pydicom.data import get_testdata_file

    found = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name in SEED_NAMES:
            path = get_testdata_file(name)
            if path is not None:
                found.append((name, Path(path).read_bytes()))
    with tempfile.TemporaryDirectory() as folder:
        from test_dicom_mosaic import Mosaic
        from test_dicom_volumes import enhanced
        from test_dicom import Series

        found.append(("mosaic", Mosaic(n=9, tile=(6, 5)).write(Path(folder) / "m").read_bytes()))
        found.append(("enhanced", enhanced(Path(folder) / "e", {1: Series(n=4)}).read_bytes()))
    return found


def element_offsets(data):
    """Offsets of probable explicit-VR element headers (tag, then a known VR)."""
    vrs = set(VRS[:-1])
    return [i for i in range(0, len(data) - 8, 2)
            if data[i + 4:i + 6] in vrs and data[i + 1] in (0x00, 0x7F, 0x30, 0x52, 0xFF)
            and data[i] % 2 == 0]


def mutate(data, offsets, kind, params):
    """Apply mutation ``kind`` to ``data`` with the integers ``params`` (>= 4 of them)."""
    a, b, c, d = params[:4]
    out = bytearray(data)
    if kind == "truncate":
        return bytes(out[:a % len(out)])
    if kind == "bitflip":
        rng = random.Random(a)
        for _ in range(1 + b % 16):
            out[rng.randrange(len(out))] ^= 1 << rng.randrange(8)
        return bytes(out)
    if kind == "splice":
        start, size = a % len(out), 1 + b % 512
        if c % 2:
            del out[start:start + size]
        else:
            out[start:start] = out[d % len(out):d % len(out) + size]
        return bytes(out)
    if kind == "lying":
        return lie(data, a, b, c)
    if not offsets:
        return bytes(out[:a % len(out)])
    at = offsets[a % len(offsets)]
    if kind == "vr":
        out[at + 4:at + 6] = VRS[b % len(VRS)]
        return bytes(out)
    # kind == "length": the 2- or 4-byte length after the VR
    value = LENGTHS[b % len(LENGTHS)] if c % 3 else d
    if bytes(out[at + 4:at + 6]) in LONG_VRS:
        out[at + 8:at + 12] = struct.pack("<I", value % 2 ** 32)
    else:
        out[at + 6:at + 8] = struct.pack("<H", value % 2 ** 16)
    return bytes(out)


def lie(data, a, b, c):
    """The file with one to three header values replaced by lies."""
    import pydicom

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            ds = pydicom.dcmread(io.BytesIO(data), force=True)
        except Exception:
            return data
        rng = random.Random(a * 7919 + b)
        for _ in range(1 + c % 3):
            keyword = rng.choice(sorted(LIES))
            try:
                setattr(ds, keyword, rng.choice(LIES[keyword]))
            except Exception:
                pass
        buffer = io.BytesIO()
        try:
            ds.save_as(buffer, enforce_file_format=False)
        except Exception:
            return data
    return buffer.getvalue()


def run_case(data, path):
    """Read ``data`` as a DICOM file: (outcome, seconds, traced peak bytes)."""
    from mipcast.io.dicom import DicomError, read_dicom

    path.write_bytes(data)
    tracemalloc.reset_peak()
    start = time.perf_counter()
    signal.setitimer(signal.ITIMER_REAL, TIME_LIMIT_S)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            read_dicom(path)
        outcome = "read"
    except DicomError as error:
        outcome = "DicomError"
        CAUSES[type(error.__cause__).__name__ if error.__cause__ is not None else "-"] += 1
    except Hang:
        outcome = "Hang"
    except Exception as error:  # undocumented: a failure
        outcome = f"UNDOCUMENTED {type(error).__name__}: {str(error)[:200]}"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
    return outcome, time.perf_counter() - start, tracemalloc.get_traced_memory()[1]


def _alarm(signum, frame):
    raise Hang()


def setup():
    signal.signal(signal.SIGALRM, _alarm)
    if not tracemalloc.is_tracing():
        tracemalloc.start()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases", type=int, default=10000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    setup()
    files = seeds()
    offsets = [element_offsets(data) for _, data in files]
    rng = random.Random(args.seed)
    outcomes = collections.Counter()
    kinds = collections.Counter()
    failures, slowest, peak = [], (0.0, ""), (0, "")
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "case.dcm"
        for case in range(args.cases):
            index = rng.randrange(len(files))
            kind = KINDS[case % len(KINDS)]
            params = [rng.getrandbits(32) for _ in range(4)]
            data = mutate(files[index][1], offsets[index], kind, params)
            outcome, seconds, traced = run_case(data, path)
            label = f"case {case}: {kind} of {files[index][0]} {params}"
            outcomes[outcome.split(":")[0]] += 1
            kinds[kind] += 1
            if outcome.startswith(("UNDOCUMENTED", "Hang")) or traced > MEMORY_BOUND:
                failures.append(f"{label}: {outcome}, {seconds:.2f} s, {traced / 2**20:.1f} MiB")
            slowest = max(slowest, (seconds, label))
            peak = max(peak, (traced, label))
    print(f"cases: {args.cases} ({dict(kinds)}), seeds: {len(files)} files "
          f"({', '.join(name for name, _ in files)}), wall {time.perf_counter() - started:.0f} s")
    print(f"outcomes: {dict(outcomes.most_common())}")
    print(f"DicomError wrapping (cause class: count): {dict(CAUSES.most_common())}")
    print(f"max time per case: {slowest[0]:.3f} s ({slowest[1]})")
    print(f"peak traced allocation per case: {peak[0] / 2**20:.1f} MiB ({peak[1]}); "
          f"bound {MEMORY_BOUND / 2**20:.0f} MiB")
    print(f"process peak RSS: {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB")
    print(f"failures: {len(failures)}")
    for line in failures[:20]:
        print("  " + line)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

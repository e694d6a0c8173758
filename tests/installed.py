"""Where the installed mipcast lives, for subprocesses that must import it.

The tests import the installed package, never the checkout.  Subprocesses
run with this interpreter find it by themselves; ParaView's pvpython (its
own Python and VTK) gets :func:`package_path`: a folder holding only a link
to the installed ``mipcast``, so nothing else of this interpreter's
site-packages (numpy 2, VTK 9.7) shadows ParaView's own.
"""
import hashlib
import os
import tempfile
from pathlib import Path

import mipcast

#: The repository checkout (tests, examples, fixtures' sources).
ROOT = Path(__file__).resolve().parents[1]


def package_path() -> str:
    """A folder for PYTHONPATH whose only entry is a link to the installed ``mipcast``."""
    target = Path(mipcast.__file__).resolve().parent
    tag = hashlib.sha1(str(target).encode()).hexdigest()[:10]  # one folder per installation
    folder = Path(tempfile.gettempdir()) / f"mipcast-pythonpath-{os.getuid()}-{tag}"
    folder.mkdir(exist_ok=True)
    link = folder / "mipcast"
    if not (link.is_symlink() and Path(os.readlink(link)) == target):
        tmp = folder / f"mipcast.{os.getpid()}"
        tmp.symlink_to(target, target_is_directory=True)
        os.replace(tmp, link)
    return str(folder)


def pvpython_env() -> dict:
    """The environment for pvpython: PYTHONPATH = :func:`package_path`, no PYTHONHOME."""
    env = dict(os.environ, PYTHONPATH=package_path())
    env.pop("PYTHONHOME", None)
    return env


#: A working folder outside the checkout, for ``python -c`` / ``-m`` subprocesses
#: (their ``sys.path[0]`` is the working folder: in the checkout it would
#: shadow the installed package).
OUTSIDE = tempfile.gettempdir()


def plain_env() -> dict:
    """The environment for this interpreter's subprocesses: no PYTHONPATH pointing at the checkout."""
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    return env


if __name__ == "__main__":  # PYTHONPATH=$(python3 tests/installed.py) xvfb-run -a pvpython tests/...
    print(package_path())

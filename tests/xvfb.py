"""Run a command under a private X server (xvfb-run), for the VTK 9.2 / ParaView checks.

An X server resets itself when its last client disconnects, and a
connection attempted during the reset fails: VTK then aborts in
``vtkXOpenGLRenderWindow::CreateAWindow`` ("bad X server connection").
With two X clients under one ``xvfb-run`` (pvserver and pvpython), one
closing its probe window while the other opens its own hit this now and
then; ``-noreset`` keeps the server up.  A display that still fails
("bad X server connection") is retried once; any other failure is
returned as it is.
"""
import json
import os
import shutil
import subprocess

from installed import ROOT, pvpython_env

#: A 24-bit screen (GLX needs a true-colour visual; xvfb-run's default is 8-bit),
#: never reset between clients.
SERVER = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24 -noreset"]
_NO_DISPLAY = ("bad X server connection", "CreateAWindow", "cannot open display")


def run_under_xvfb(command, **kwargs) -> subprocess.CompletedProcess:
    """``subprocess.run(SERVER + command, capture_output=True, text=True, **kwargs)``, retried once if X failed."""
    for _ in range(2):
        result = subprocess.run(SERVER + list(command), capture_output=True, text=True, **kwargs)
        if result.returncode == 0 or not any(text in result.stderr for text in _NO_DISPLAY):
            return result
    return result


def pvpython_report(check, what: str, timeout: float = 240) -> dict:
    """Run ``tests/<check>`` in pvpython under xvfb and return the JSON of its last ``{`` line.

    Skips the calling test (``pytest.skip``) when pvpython or xvfb-run is
    missing; ``what`` names the test in that message.  Fails with the
    script's output if it exits non-zero or prints no report.
    """
    import pytest

    missing = [tool for tool in ("pvpython", "xvfb-run") if shutil.which(tool) is None]
    if missing:
        pytest.skip(f"{' and '.join(missing)} not on PATH: {what} needs "
                    "Debian's paraview, python3-paraview and xvfb")
    completed = run_under_xvfb(["pvpython", str(ROOT / "tests" / check)], cwd=ROOT, env=pvpython_env(),
                               timeout=timeout)
    lines = [line for line in completed.stdout.splitlines() if line.startswith("{")]
    assert completed.returncode == 0 and lines, (
        f"pvpython exited with {completed.returncode}\nstdout:\n{completed.stdout[-3000:]}"
        f"\nstderr:\n{completed.stderr[-3000:]}")
    return json.loads(lines[-1])


def private_display():
    """A generator for a module fixture: one private X server, yielding its display (e.g. ``":7"``).

    ``-displayfd`` has the server choose a free display; ``-noreset`` keeps
    it from resetting when its last client leaves (a rank connecting during
    a reset fails: "bad X server connection").  Use as
    ``display = pytest.fixture(scope="module")(private_display)``.
    """
    import pytest

    read, write = os.pipe()
    server = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "1280x1024x24", "-nolisten", "tcp",
                               "-noreset"], pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write)
    with os.fdopen(read) as pipe:
        number = pipe.readline().strip()
    if not number:
        server.kill()
        pytest.fail("Xvfb did not start")
    yield f":{number}"
    server.terminate()
    server.wait(timeout=30)


def mpi_env(display) -> dict:
    """``pvpython_env()`` on ``display``, with Open MPI allowed to run as root (CI runs as root)."""
    env = pvpython_env()
    env.update(DISPLAY=display, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    return env

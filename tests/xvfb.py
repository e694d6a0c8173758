"""Run a command under a private X server, for the VTK 9.2 / ParaView checks.

Every call gets an X server of its own: ``Xvfb -displayfd`` picks a free
display itself, so runs in parallel test workers (pytest-xdist) never share
or race for one (``xvfb-run -a`` probes for a free number and can hand two
callers the same).  The server runs with ``-noreset``: an X server resets
itself when its last client disconnects, and a connection attempted during
the reset fails (VTK then aborts in ``vtkXOpenGLRenderWindow::CreateAWindow``,
"bad X server connection"); with two X clients on one server (pvserver and
pvpython) one closing its probe window while the other opens its own hit
this now and then.  A run that still fails to reach its display is retried
once; any other failure is returned as it is.
"""
import json
import os
import shutil
import subprocess
from contextlib import contextmanager

from installed import ROOT, pvpython_env

#: A 24-bit screen (GLX needs a true-colour visual; xvfb-run's default is 8-bit),
#: never reset between clients, no TCP.
XVFB_ARGS = ["-screen", "0", "1280x1024x24", "-nolisten", "tcp", "-noreset"]
_NO_DISPLAY = ("bad X server connection", "CreateAWindow", "cannot open display")


@contextmanager
def xvfb_display():
    """A private X server for the ``with`` block, yielding its display (e.g. ``":7"``)."""
    read, write = os.pipe()
    server = subprocess.Popen(["Xvfb", "-displayfd", str(write)] + XVFB_ARGS, pass_fds=(write,),
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write)
    with os.fdopen(read) as pipe:
        number = pipe.readline().strip()
    try:
        if not number:
            raise RuntimeError(f"Xvfb did not start (exit status {server.poll()})")
        yield f":{number}"
    finally:
        server.terminate()
        try:
            server.wait(timeout=30)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()


def run_under_xvfb(command, env=None, **kwargs) -> subprocess.CompletedProcess:
    """``subprocess.run(command, capture_output=True, text=True, **kwargs)`` on a private X server.

    ``env`` (default: this process's environment) gets that server's
    ``DISPLAY``; a run that failed to reach it is retried once.
    """
    env = dict(os.environ if env is None else env)
    for _ in range(2):
        with xvfb_display() as display:
            env["DISPLAY"] = display
            result = subprocess.run(list(command), capture_output=True, text=True, env=env, **kwargs)
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

    missing = [tool for tool in ("pvpython", "Xvfb") if shutil.which(tool) is None]
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

    Use as ``display = pytest.fixture(scope="module")(private_display)``.
    """
    import pytest

    try:
        with xvfb_display() as display:
            yield display
    except RuntimeError as error:
        pytest.fail(str(error))


def mpi_env(display) -> dict:
    """``pvpython_env()`` on ``display``, with Open MPI allowed to run as root (CI runs as root)."""
    env = pvpython_env()
    env.update(DISPLAY=display, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    return env

"""Run a command under a private X server (xvfb-run), for the VTK 9.2 / ParaView checks.

``xvfb-run -a`` can occasionally fail to give the client a display on a
busy machine: VTK then aborts in ``vtkXOpenGLRenderWindow::CreateAWindow``
("bad X server connection") before any of our code runs.  That one failure
is retried once; any other failure is returned as it is.
"""
import subprocess

#: A 24-bit screen: GLX needs a true-colour visual (xvfb-run's default is 8-bit).
SERVER = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24"]
_NO_DISPLAY = ("bad X server connection", "CreateAWindow", "cannot open display")


def run_under_xvfb(command, **kwargs) -> subprocess.CompletedProcess:
    """``subprocess.run(SERVER + command, capture_output=True, text=True, **kwargs)``, retried once if X failed."""
    for _ in range(2):
        result = subprocess.run(SERVER + list(command), capture_output=True, text=True, **kwargs)
        if result.returncode == 0 or not any(text in result.stderr for text in _NO_DISPLAY):
            return result
    return result

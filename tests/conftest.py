"""Shared test settings: markers and small scenes (volumes <= 64^3, images <= 128^2).

The tests run with ``--import-mode=importlib`` against the *installed*
mipcast; this folder goes on ``sys.path`` only so that the tests' own helper
modules (``xvfb``, ``installed``, ``vtk_png``) import.
"""
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: takes more than ~30 s; deselect with -m 'not slow'")


@pytest.fixture(scope="session")
def vessels48():
    from mipcast.data_fixtures import make_fixture
    return make_fixture("vessels", size=48)

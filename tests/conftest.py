"""Shared test settings: markers and small scenes (volumes <= 64^3, images <= 128^2)."""
import pytest


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: takes more than ~30 s; deselect with -m 'not slow'")


@pytest.fixture(scope="session")
def vessels48():
    from mipcast.data_fixtures import make_fixture
    return make_fixture("vessels", size=48)

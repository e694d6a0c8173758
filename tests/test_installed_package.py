"""The tests run against the installed package, not the checkout."""
import os
from pathlib import Path

import pytest

import mipcast
from installed import ROOT


@pytest.mark.skipif(not os.environ.get("CI"), reason="CI only: developers may test an editable install")
def test_mipcast_is_imported_from_the_installed_package_not_the_checkout():
    location = Path(mipcast.__file__).resolve()
    assert ROOT not in location.parents, (
        f"mipcast was imported from the checkout ({location}); CI must test the installed package")


def test_the_top_level_folders_are_installed_inside_the_package():
    import mipcast.data_fixtures
    import mipcast.filters
    import mipcast.shaders

    package = Path(mipcast.__file__).resolve().parent
    for module in (mipcast.filters, mipcast.shaders, mipcast.data_fixtures):
        assert Path(module.__file__).resolve().parent.parent == package, module.__file__
    assert list((package / "shaders").glob("*.glsl")), "the GLSL pieces are not package data"

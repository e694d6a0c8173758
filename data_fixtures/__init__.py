"""Test volumes: seeded synthetic phantoms and a real head CT.

See ``README.md`` in this package for what each fixture is and its licence.
"""
from mipcast.data_fixtures.ct_phantom import ct_volume
from mipcast.data_fixtures.head_ct import head_ct_path, load_head_ct
from mipcast.data_fixtures.synthetic import FIXTURES, image_from_array, make_fixture

__all__ = ["FIXTURES", "ct_volume", "make_fixture", "image_from_array", "head_ct_path", "load_head_ct"]

"""The parameter tables: every entry checks its own default, setters and getters come from them."""
import pytest

from mipcast.core.parameters import Parameter
from mipcast.methods import METHODS


def _entries():
    return [(name, p) for name, m in METHODS.items() for p in m.parameters]


@pytest.mark.parametrize("name, parameter", _entries(), ids=lambda v: getattr(v, "name", v))
def test_every_default_passes_its_own_check_and_round_trips(name, parameter):
    mapper = METHODS[name].create()
    value = getattr(mapper, parameter.getter)()
    assert value == parameter.default
    values = value if parameter.variadic and isinstance(value, tuple) else (value,)
    getattr(mapper, parameter.setter)(*values)
    assert getattr(mapper, parameter.getter)() == parameter.default


@pytest.mark.parametrize("name, parameter", [e for e in _entries() if e[1].kind == "bool"],
                         ids=lambda v: getattr(v, "name", v))
def test_booleans_refuse_text_instead_of_taking_its_truth_value(name, parameter):
    mapper = METHODS[name].create()
    with pytest.raises(TypeError, match=parameter.name):
        getattr(mapper, parameter.setter)("off")
    getattr(mapper, parameter.setter)(0)
    assert getattr(mapper, parameter.getter)() is False


def test_a_range_check_names_the_parameter_and_the_range():
    p = Parameter("gain", "float", 0.5, "How much.", low=0.0, high=1.0)
    with pytest.raises(ValueError, match=r"gain must be in \[0, 1\]"):
        p.check(2.0)
    levels = Parameter("levels", "int", 3, "How many.", low=1, high=5)
    with pytest.raises(ValueError, match="levels must be an integer from 1 to 5"):
        levels.check(7)
    assert levels.describe() == "int in [1, 5], default 3"

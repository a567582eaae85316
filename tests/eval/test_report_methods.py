"""`restircl report`'s method names with settings changed (eval/report/methods.py): `base+key=value`."""

import pytest
from restircl.eval.report.methods import method_overrides, method_settings


def test_a_plain_name_is_its_overrides():
    assert method_overrides("restir_temporal") == {"method": "restir", "spatial": False}


def test_settings_changed_take_the_type_of_their_default():
    assert method_overrides("restir+m_cap=5+candidates=16+spatial=false+boiling_mode=forget") == {
        "method": "restir", "m_cap": 5.0, "candidates": 16, "spatial": False, "boiling_mode": "forget"}
    s = method_settings("ris+candidates=24", None, 7)
    assert (s.method, s.candidates, s.seed) == ("ris", 24, 7)
    assert isinstance(method_overrides("restir+spatial_radius=10")["spatial_radius"], float)


@pytest.mark.parametrize("name", ["nope", "restir+m_cap", "restir+no_such_setting=1", "restir+spatial=maybe",
                                  "restir+candidates=many"])
def test_a_wrong_name_fails(name):
    with pytest.raises(ValueError):
        method_overrides(name)

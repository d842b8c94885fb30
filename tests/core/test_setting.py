"""A footprint point's control setting (core.setting, issue 26): typed in the core, and stored, sent and read back as
the dict the service's rows, CSV and page have always held."""

import pytest
from hypothesis import given
from hypothesis import strategies as st

from footprint.core.setting import ControlSetting

STORED = [  # the stored forms each method wrote before the record was typed (rows in the database keep them)
    ({"bank0_deg": 45.0, "bank_gain": 0.5}, "initial bank 45°"),
    ({"bank_gain": 0.67, "sigma_f_deg": -15.0}, "K 0.67, σf -15°"),
    ({"bank_deg": 30.0, "turn_deg": 90.0}, "bank 30°, wings level after a turn of 90°"),
    ({"turn_deg": 38.2, "until": "wings_level"}, "wings level after a turn of 38.2°"),
    ({"min_range": "cl_max"}, "C_L max, no bank (shortest flight)"),
    ({"bank0_deg": 105.0, "bank_gain": 105.0 / 90.0, "alpha_floor_deg": 21.5}, "initial bank 105°, α floor 21.5°"),
    (
        {
            "downrange_target_nmi": None,
            "iterations": 41,
            "nlp_downrange_nmi": 5012.5,
            "nlp_crossrange_nmi": 930.25,
            "agreement_deg": 0.0004,
        },
        "re-flown within 0.0004°, IPOPT iterations 41",
    ),
]


@pytest.mark.parametrize("stored, words", STORED)
def test_a_stored_setting_reads_back_to_the_same_dict_and_says_itself_in_words(stored, words):
    setting = ControlSetting.of(stored)
    assert setting.as_dict() == stored and list(setting.as_dict()) == list(stored)  # same keys, same order
    assert setting.words() == words


def test_a_stored_setting_with_a_field_no_method_writes_is_refused():
    with pytest.raises(TypeError):
        ControlSetting.of({"bank0_deg": 45.0, "gain": 0.5})


finite = st.floats(-1e4, 1e4, allow_nan=False)


@given(
    st.builds(ControlSetting, bank0_deg=st.none() | finite, bank_gain=st.none() | finite, turn_deg=st.none() | finite)
)
def test_the_stored_form_round_trips_and_its_key_tells_settings_apart(setting):
    assert ControlSetting.of(setting.as_dict()) == setting
    other = ControlSetting(bank0_deg=(setting.bank0_deg or 0.0) + 1.0, bank_gain=setting.bank_gain)
    assert (setting.key() == other.key()) == (setting == other)

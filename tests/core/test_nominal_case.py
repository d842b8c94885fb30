"""The report's nominal case (Table 2 entry, zero bank, (L/D)max, stop at 50,000 ft) against what its text states."""

import pytest

from footprint import fly
from tests.authorities.report import REPORT, table2_entry, table2_stop


def nominal(vehicle, gamma_deg=REPORT["table2.gamma_deg"].value):
    return fly(
        {
            "vehicle": {"builtin": vehicle},
            "entry": table2_entry(gamma_deg=gamma_deg),
            "alpha": {"law": "max_ld"},
            "bank": {"law": "zero"},
            "stop": table2_stop(),
        }
    ).summary


def test_lod_189_zero_bank_reaches_the_reported_maximum_downrange():
    # Section III's maximum down-range (L/D 1.89, 70 psf); B-1 is synthesized, so 10 %
    s = nominal("lod-1.89")
    assert s["downrange_nmi"] == pytest.approx(REPORT["sec3.max_downrange_nmi"].value, rel=0.10)
    assert s["stop_reason"] == "altitude"


@pytest.mark.parametrize("gamma_deg", [-2.0, -3.0, -4.0, -5.0])
def test_pullout_is_about_the_same_for_ld_22_and_26_and_lower_for_the_heavier_189(gamma_deg):
    # Fig. 16 text: "approximately the same for L/D 2.2 and 2.6"; it depends on W/(C_L S): 70 psf pulls out lower
    h22, h26, h189 = (nominal(v, gamma_deg)["pullout_altitude_ft"] for v in ("lod-2.2", "lod-2.6", "lod-1.89"))
    assert abs(h22 - h26) < 0.03 * h22
    assert h189 < min(h22, h26) - 3_000


def test_steeper_entries_pull_out_lower():
    alts = [nominal("lod-2.2", g)["pullout_altitude_ft"] for g in (-2.0, -3.0, -4.0, -5.0)]
    assert all(a > b for a, b in zip(alts, alts[1:]))

"""The validation report (slow: it flies every footprint of docs/validation.md)."""

import importlib.util
from pathlib import Path

import pytest

from tests.authorities.report import REPORT

_SCRIPT = Path(__file__).parents[1] / "scripts" / "validation.py"  # a script that writes docs/, not the package's
_spec = importlib.util.spec_from_file_location("validation", _SCRIPT)
validation = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(validation)


@pytest.mark.slow
def test_validation_report_is_written_with_every_number_and_figure(tmp_path):
    validation.main(["--out", str(tmp_path)])
    text = (tmp_path / "validation.md").read_text()
    published = [
        f"{REPORT[k].value:,.0f} {REPORT[k].unit}"
        for k in (
            "sec3.max_crossrange_nmi",
            "sec3.max_downrange_nmi",
            "appc.max_crossrange_single_parameter_nmi",
            "appc.max_crossrange_constant_altitude_nmi",
            "table2.inertial_velocity_fps",
        )
    ]
    for needle in (*published, "Where and why we differ"):
        assert needle in text
    pngs = sorted(p.name for p in (tmp_path / "figures").glob("*.png"))
    assert "figC21_C46_medium_lod.png" in pngs and "fig12_lod189_single_parameter.png" in pngs
    assert all((tmp_path / "figures" / n).stat().st_size > 10_000 for n in pngs)

"""The validation report (slow: it flies every footprint of docs/validation.md)."""

import importlib.util
from pathlib import Path

import pytest

_SCRIPT = Path(__file__).parents[1] / "scripts" / "validation.py"  # a script that writes docs/, not the package's
_spec = importlib.util.spec_from_file_location("validation", _SCRIPT)
validation = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(validation)


@pytest.mark.slow
def test_validation_report_is_written_with_every_number_and_figure(tmp_path):
    validation.main(["--out", str(tmp_path)])
    text = (tmp_path / "validation.md").read_text()
    for needle in ("1,964 nmi", "14,500 nmi", "3,200 nmi", "930 nmi", "26,031 ft/s", "Where and why we differ"):
        assert needle in text
    pngs = sorted(p.name for p in (tmp_path / "figures").glob("*.png"))
    assert "figC21_C46_medium_lod.png" in pngs and "fig12_lod189_single_parameter.png" in pngs
    assert all((tmp_path / "figures" / n).stat().st_size > 10_000 for n in pngs)

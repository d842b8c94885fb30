"""The bank gain K of the single- and two-parameter laws is `bank_gain` (issue 14; it was `k`): stored studies (a
job's, a footprint's) and stored points' parameters are renamed, so a restart can submit a pending job again and a
stored footprint still names its K. The planet's zonal `k` keeps its name.

Revision ID: 2026_12_02_0003
Revises: 2026_12_02_0002
Create Date: 2026-12-02 05:00:00
"""

import sqlalchemy as sa
from alembic import op

revision = "2026_12_02_0003"
down_revision = "2026_12_02_0002"
branch_labels = None
depends_on = None

GAIN_LAWS = {"single_parameter", "two_parameter"}  # bank laws whose K was "k"
PARAMETER_KEYS = {"bank0_deg", "sigma_f_deg", "alpha_floor_deg"}  # a footprint point's parameter that carries K


def _holds_gain(d: dict) -> bool:
    return d.get("law") in GAIN_LAWS or d.get("method") == "two_parameter" or bool(PARAMETER_KEYS & set(d))


def _renamed(value, old: str, new: str):
    """The JSON value with K's key renamed wherever it means the bank gain (never the planet's zonal k)."""
    if isinstance(value, list):
        return [_renamed(v, old, new) for v in value]
    if not isinstance(value, dict):
        return value
    out = {k: _renamed(v, old, new) for k, v in value.items()}
    if old in out and _holds_gain(out):
        out[new] = out.pop(old)
    return out


def _rename(old: str, new: str) -> None:
    bind = op.get_bind()
    for table, keys, column in (
        ("jobs", ("id",), "study"),
        ("footprints", ("id",), "study"),
        ("footprint_points", ("footprint_id", "interior", "seq"), "parameter"),
    ):
        t = sa.table(table, *(sa.column(k) for k in keys), sa.column(column, sa.JSON()))
        for row in bind.execute(sa.select(t)).mappings().all():
            value = _renamed(row[column], old, new)
            if value != row[column]:
                bind.execute(t.update().where(*(t.c[k] == row[k] for k in keys)).values({column: value}))


def upgrade() -> None:
    _rename("k", "bank_gain")


def downgrade() -> None:
    _rename("bank_gain", "k")

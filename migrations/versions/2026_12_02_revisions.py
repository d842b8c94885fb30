"""A revision counter for each kind of stored thing a GET serves from its cache (footprints, vehicles): every
write of one bumps its counter in the same transaction, and a cached response is valid for one value, in any
API process over the database (issue 15 item 9: reads under load).

Revision ID: 2026_12_02_0005
Revises: 2026_12_02_0004
Create Date: 2026-12-02 08:00:00
"""

import sqlalchemy as sa
from alembic import op

revision = "2026_12_02_0005"
down_revision = "2026_12_02_0004"
branch_labels = None
depends_on = None


def upgrade() -> None:
    revisions = op.create_table(
        "revisions",
        sa.Column("name", sa.String(length=32), nullable=False),
        sa.Column("value", sa.BigInteger(), nullable=False),
        sa.PrimaryKeyConstraint("name", name=op.f("pk_revisions")),
    )
    op.bulk_insert(revisions, [{"name": "footprints", "value": 0}, {"name": "vehicles", "value": 0}])


def downgrade() -> None:
    op.drop_table("revisions")

"""A custom vehicle keeps its list item's numbers (summary: wing loading, (L/D)max and its alpha at Mach 20,
200,000 ft), computed once when it is stored: GET /api/vehicles rebuilt every vehicle's tables on each request
(issue 15 item 8). Vehicles stored before this revision have none and are summarized as they are listed.

Revision ID: 2026_12_02_0004
Revises: 2026_12_02_0003
Create Date: 2026-12-02 05:30:00
"""

import sqlalchemy as sa
from alembic import op

revision = "2026_12_02_0004"
down_revision = "2026_12_02_0003"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("vehicles", schema=None) as batch_op:
        batch_op.add_column(sa.Column("summary", sa.JSON(), nullable=True))


def downgrade() -> None:
    with op.batch_alter_table("vehicles", schema=None) as batch_op:
        batch_op.drop_column("summary")

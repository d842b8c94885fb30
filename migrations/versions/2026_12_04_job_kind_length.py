"""A job's kind up to 32 characters: "guided_dispersion" (issue 27) has 17, the column had 16.

Revision ID: 2026_12_04_0001
Revises: 2026_12_02_0005
Create Date: 2026-12-04 05:40:00
"""

import sqlalchemy as sa
from alembic import op

revision = "2026_12_04_0001"
down_revision = "2026_12_02_0005"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("jobs", schema=None) as batch_op:
        batch_op.alter_column("kind", existing_type=sa.String(length=16), type_=sa.String(length=32))


def downgrade() -> None:
    with op.batch_alter_table("jobs", schema=None) as batch_op:
        batch_op.alter_column("kind", existing_type=sa.String(length=32), type_=sa.String(length=16))

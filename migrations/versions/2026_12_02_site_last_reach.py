"""Landing sites keep the verdict of their last stored reach (last_reach), shown again after a reload.

Revision ID: 2026_12_02_0002
Revises: 2026_12_02_0001
Create Date: 2026-12-02 02:50:00
"""

import sqlalchemy as sa
from alembic import op

revision = "2026_12_02_0002"
down_revision = "2026_12_02_0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("sites", schema=None) as batch_op:
        batch_op.add_column(sa.Column("last_reach", sa.JSON(), nullable=True))


def downgrade() -> None:
    with op.batch_alter_table("sites", schema=None) as batch_op:
        batch_op.drop_column("last_reach")

"""Initial schema: vehicles, jobs, job results, footprints with points and ground tracks, landing sites.

Revision ID: 2026_11_23_0001
Revises:
Create Date: 2026-11-23 12:33:22.271680
"""

import sqlalchemy as sa
from alembic import op

revision = "2026_11_23_0001"
down_revision = None
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "jobs",
        sa.Column("id", sa.String(length=36), nullable=False),
        sa.Column("kind", sa.String(length=16), nullable=False),
        sa.Column("name", sa.String(length=200), nullable=True),
        sa.Column("status", sa.String(length=16), nullable=False),
        sa.Column("progress", sa.Float(), nullable=False),
        sa.Column("error", sa.Text(), nullable=True),
        sa.Column("study", sa.JSON(), nullable=False),
        sa.Column("attempts", sa.Integer(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("started_at", sa.DateTime(timezone=True), nullable=True),
        sa.Column("finished_at", sa.DateTime(timezone=True), nullable=True),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_jobs")),
    )
    with op.batch_alter_table("jobs", schema=None) as batch_op:
        batch_op.create_index(batch_op.f("ix_jobs_created_at"), ["created_at"], unique=False)
        batch_op.create_index("ix_jobs_kind_status", ["kind", "status"], unique=False)
        batch_op.create_index(batch_op.f("ix_jobs_status"), ["status"], unique=False)

    op.create_table(
        "sites",
        sa.Column("id", sa.Integer(), autoincrement=True, nullable=False),
        sa.Column("name", sa.String(length=200), nullable=False),
        sa.Column("latitude_deg", sa.Float(), nullable=False),
        sa.Column("longitude_deg", sa.Float(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_sites")),
    )
    op.create_table(
        "vehicles",
        sa.Column("id", sa.String(length=64), nullable=False),
        sa.Column("description", sa.Text(), nullable=False),
        sa.Column("definition", sa.JSON(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_vehicles")),
    )
    op.create_table(
        "footprints",
        sa.Column("id", sa.String(length=36), nullable=False),
        sa.Column("job_id", sa.String(length=36), nullable=False),
        sa.Column("seq", sa.Integer(), nullable=False),
        sa.Column("name", sa.String(length=300), nullable=False),
        sa.Column("vehicle", sa.String(length=200), nullable=False),
        sa.Column("method", sa.String(length=32), nullable=False),
        sa.Column("entry_latitude_deg", sa.Float(), nullable=False),
        sa.Column("entry_longitude_deg", sa.Float(), nullable=False),
        sa.Column("entry_heading_deg", sa.Float(), nullable=False),
        sa.Column("entry_velocity_fps", sa.Float(), nullable=False),
        sa.Column("entry_gamma_deg", sa.Float(), nullable=False),
        sa.Column("entry_altitude_ft", sa.Float(), nullable=False),
        sa.Column("area_nmi2", sa.Float(), nullable=False),
        sa.Column("max_crossrange_nmi", sa.Float(), nullable=False),
        sa.Column("max_downrange_nmi", sa.Float(), nullable=False),
        sa.Column("min_downrange_nmi", sa.Float(), nullable=False),
        sa.Column("trajectories", sa.Integer(), nullable=False),
        sa.Column("study", sa.JSON(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.ForeignKeyConstraint(["job_id"], ["jobs.id"], name=op.f("fk_footprints_job_id_jobs"), ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_footprints")),
        sa.UniqueConstraint("job_id", "seq", name=op.f("uq_footprints_job_id")),
    )
    with op.batch_alter_table("footprints", schema=None) as batch_op:
        batch_op.create_index(batch_op.f("ix_footprints_created_at"), ["created_at"], unique=False)
        batch_op.create_index(batch_op.f("ix_footprints_job_id"), ["job_id"], unique=False)

    op.create_table(
        "job_results",
        sa.Column("job_id", sa.String(length=36), nullable=False),
        sa.Column("result", sa.JSON(), nullable=False),
        sa.Column("created_at", sa.DateTime(timezone=True), nullable=False),
        sa.ForeignKeyConstraint(["job_id"], ["jobs.id"], name=op.f("fk_job_results_job_id_jobs"), ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("job_id", name=op.f("pk_job_results")),
    )
    op.create_table(
        "footprint_points",
        sa.Column("footprint_id", sa.String(length=36), nullable=False),
        sa.Column("interior", sa.Boolean(), nullable=False),
        sa.Column("seq", sa.Integer(), nullable=False),
        sa.Column("downrange_nmi", sa.Float(), nullable=False),
        sa.Column("crossrange_nmi", sa.Float(), nullable=False),
        sa.Column("flight_time_s", sa.Float(), nullable=False),
        sa.Column("latitude_deg", sa.Float(), nullable=False),
        sa.Column("longitude_deg", sa.Float(), nullable=False),
        sa.Column("heading_deg", sa.Float(), nullable=False),
        sa.Column("side", sa.String(length=8), nullable=False),
        sa.Column("parameter", sa.JSON(), nullable=False),
        sa.Column("stop_reason", sa.String(length=32), nullable=False),
        sa.Column("mirrored", sa.Boolean(), nullable=False),
        sa.ForeignKeyConstraint(
            ["footprint_id"],
            ["footprints.id"],
            name=op.f("fk_footprint_points_footprint_id_footprints"),
            ondelete="CASCADE",
        ),
        sa.PrimaryKeyConstraint("footprint_id", "interior", "seq", name=op.f("pk_footprint_points")),
    )
    op.create_table(
        "trajectories",
        sa.Column("id", sa.Integer(), autoincrement=True, nullable=False),
        sa.Column("footprint_id", sa.String(length=36), nullable=False),
        sa.Column("kind", sa.String(length=32), nullable=False),
        sa.Column("summary", sa.JSON(), nullable=False),
        sa.Column("time_s", sa.JSON(), nullable=False),
        sa.Column("latitude_deg", sa.JSON(), nullable=False),
        sa.Column("longitude_deg", sa.JSON(), nullable=False),
        sa.ForeignKeyConstraint(
            ["footprint_id"],
            ["footprints.id"],
            name=op.f("fk_trajectories_footprint_id_footprints"),
            ondelete="CASCADE",
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_trajectories")),
        sa.UniqueConstraint("footprint_id", name=op.f("uq_trajectories_footprint_id")),
    )


def downgrade() -> None:
    op.drop_table("trajectories")
    op.drop_table("footprint_points")
    op.drop_table("job_results")
    with op.batch_alter_table("footprints", schema=None) as batch_op:
        batch_op.drop_index(batch_op.f("ix_footprints_job_id"))
        batch_op.drop_index(batch_op.f("ix_footprints_created_at"))

    op.drop_table("footprints")
    op.drop_table("vehicles")
    op.drop_table("sites")
    with op.batch_alter_table("jobs", schema=None) as batch_op:
        batch_op.drop_index(batch_op.f("ix_jobs_status"))
        batch_op.drop_index("ix_jobs_kind_status")
        batch_op.drop_index(batch_op.f("ix_jobs_created_at"))

    op.drop_table("jobs")

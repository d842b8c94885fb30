"""SQLAlchemy 2 typed declarative models: vehicles, jobs and their results, footprints with their points and
ground tracks, landing sites. Constraint names follow one convention so SQLite and Postgres agree."""

from datetime import UTC, datetime
from typing import Any

from sqlalchemy import (
    JSON,
    BigInteger,
    Boolean,
    DateTime,
    Float,
    ForeignKey,
    Index,
    Integer,
    MetaData,
    String,
    Text,
    UniqueConstraint,
)
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column, relationship

from footprint.contracts.bounds import (
    FOOTPRINT_NAME_CHARS,
    JOB_NAME_CHARS,
    PROGRESS_NOTE_CHARS,
    SITE_NAME_CHARS,
    VEHICLE_ID_CHARS,
    VEHICLE_NAME_CHARS,
)

NAMING = {
    "ix": "ix_%(column_0_label)s",
    "uq": "uq_%(table_name)s_%(column_0_name)s",
    "ck": "ck_%(table_name)s_%(constraint_name)s",
    "fk": "fk_%(table_name)s_%(column_0_name)s_%(referred_table_name)s",
    "pk": "pk_%(table_name)s",
}

JOB_STATUSES = ("queued", "running", "succeeded", "failed", "cancelled")
PENDING = ("queued", "running")
MAX_INTEGER = 2_147_483_647  # an Integer column's largest value (Postgres int4): the bound of ids and list offsets


def utc_now() -> datetime:
    return datetime.now(UTC)


class Base(DeclarativeBase):
    metadata = MetaData(naming_convention=NAMING)
    type_annotation_map = {dict[str, Any]: JSON, list[Any]: JSON, datetime: DateTime(timezone=True)}


class Revision(Base):
    """How many writes each kind of stored thing (REVISIONS) has had: a cached GET response is valid for one value
    (service.read_cache), in every API process over the database."""

    __tablename__ = "revisions"
    name: Mapped[str] = mapped_column(String(32), primary_key=True)
    value: Mapped[int] = mapped_column(BigInteger)


REVISIONS = ("footprints", "vehicles")


class Vehicle(Base):
    """A custom vehicle: its definition is the case contract's vehicle object."""

    __tablename__ = "vehicles"
    id: Mapped[str] = mapped_column(String(VEHICLE_ID_CHARS), primary_key=True)
    description: Mapped[str] = mapped_column(Text, default="")
    definition: Mapped[dict[str, Any]]
    # the list item's numbers (wing_loading_psf, ld_max, alpha_ld_max_deg), computed once when it is stored
    summary: Mapped[dict[str, Any] | None]
    created_at: Mapped[datetime] = mapped_column(default=utc_now)


class Job(Base):
    __tablename__ = "jobs"
    id: Mapped[str] = mapped_column(String(36), primary_key=True)
    kind: Mapped[str] = mapped_column(String(32))  # a contracts.MODULES kind
    name: Mapped[str | None] = mapped_column(String(JOB_NAME_CHARS))
    status: Mapped[str] = mapped_column(String(16), index=True)
    progress: Mapped[float] = mapped_column(Float, default=0.0)
    progress_note: Mapped[str | None] = mapped_column(
        String(PROGRESS_NOTE_CHARS)
    )  # what a running job is doing (IPOPT's iteration)
    error: Mapped[str | None] = mapped_column(Text)
    study: Mapped[dict[str, Any]]
    attempts: Mapped[int] = mapped_column(Integer, default=0)  # submissions to the cluster (restarts add one)
    created_at: Mapped[datetime] = mapped_column(default=utc_now, index=True)
    started_at: Mapped[datetime | None]
    finished_at: Mapped[datetime | None]
    result: Mapped["JobResult | None"] = relationship(back_populates="job", cascade="all, delete-orphan")


class JobResult(Base):
    """A job's result, written once: the primary key on job_id makes a second write fail."""

    __tablename__ = "job_results"
    job_id: Mapped[str] = mapped_column(ForeignKey("jobs.id", ondelete="CASCADE"), primary_key=True)
    result: Mapped[dict[str, Any]]
    created_at: Mapped[datetime] = mapped_column(default=utc_now)
    job: Mapped[Job] = relationship(back_populates="result")


class Footprint(Base):
    __tablename__ = "footprints"
    __table_args__ = (UniqueConstraint("job_id", "seq"),)  # a job's footprints, each written once
    id: Mapped[str] = mapped_column(String(36), primary_key=True)
    job_id: Mapped[str] = mapped_column(ForeignKey("jobs.id", ondelete="CASCADE"), index=True)
    seq: Mapped[int] = mapped_column(Integer)  # the footprint's place in its job
    name: Mapped[str] = mapped_column(String(FOOTPRINT_NAME_CHARS))
    vehicle: Mapped[str] = mapped_column(String(VEHICLE_NAME_CHARS))
    method: Mapped[str] = mapped_column(String(32))
    entry_latitude_deg: Mapped[float] = mapped_column(Float)
    entry_longitude_deg: Mapped[float] = mapped_column(Float)
    entry_heading_deg: Mapped[float] = mapped_column(Float)
    entry_velocity_fps: Mapped[float] = mapped_column(Float)
    entry_gamma_deg: Mapped[float] = mapped_column(Float)
    entry_altitude_ft: Mapped[float] = mapped_column(Float)
    area_nmi2: Mapped[float] = mapped_column(Float)
    max_crossrange_nmi: Mapped[float] = mapped_column(Float)
    max_downrange_nmi: Mapped[float] = mapped_column(Float)
    min_downrange_nmi: Mapped[float] = mapped_column(Float)
    trajectories: Mapped[int] = mapped_column(Integer)
    study: Mapped[dict[str, Any]]  # the footprint study that produced it (flown again by an "exact" transform)
    created_at: Mapped[datetime] = mapped_column(default=utc_now, index=True)
    points: Mapped[list["FootprintPoint"]] = relationship(cascade="all, delete-orphan", passive_deletes=True)
    ground_track: Mapped["Trajectory | None"] = relationship(cascade="all, delete-orphan", passive_deletes=True)


class FootprintPoint(Base):
    """A boundary point (in order; the last joins the first) or an interior point of a footprint."""

    __tablename__ = "footprint_points"
    footprint_id: Mapped[str] = mapped_column(ForeignKey("footprints.id", ondelete="CASCADE"), primary_key=True)
    interior: Mapped[bool] = mapped_column(Boolean, primary_key=True)
    seq: Mapped[int] = mapped_column(Integer, primary_key=True)
    downrange_nmi: Mapped[float] = mapped_column(Float)
    crossrange_nmi: Mapped[float] = mapped_column(Float)
    flight_time_s: Mapped[float] = mapped_column(Float)
    latitude_deg: Mapped[float] = mapped_column(Float)
    longitude_deg: Mapped[float] = mapped_column(Float)
    heading_deg: Mapped[float] = mapped_column(Float)
    side: Mapped[str] = mapped_column(String(8))
    parameter: Mapped[dict[str, Any]]
    stop_reason: Mapped[str] = mapped_column(String(32))
    mirrored: Mapped[bool] = mapped_column(Boolean)


class Trajectory(Base):
    """A footprint's zero-bank ground track, decimated (arrays of at most 500 samples)."""

    __tablename__ = "trajectories"
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    footprint_id: Mapped[str] = mapped_column(ForeignKey("footprints.id", ondelete="CASCADE"), unique=True)
    kind: Mapped[str] = mapped_column(String(32), default="zero_bank")
    summary: Mapped[dict[str, Any]]
    time_s: Mapped[list[Any]]
    latitude_deg: Mapped[list[Any]]
    longitude_deg: Mapped[list[Any]]


class Site(Base):
    __tablename__ = "sites"
    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    name: Mapped[str] = mapped_column(String(SITE_NAME_CHARS))
    latitude_deg: Mapped[float] = mapped_column(Float)
    longitude_deg: Mapped[float] = mapped_column(Float)
    last_reach: Mapped[
        dict[str, Any] | None
    ]  # the verdict of the last reach stored for it (POST /api/reach?store_verdicts=true)
    created_at: Mapped[datetime] = mapped_column(default=utc_now)


Index("ix_jobs_kind_status", Job.kind, Job.status)

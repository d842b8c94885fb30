"""Every query of the service, as keyword-only functions taking a session. Callers own the transaction
(`with sessions.begin() as s:`), except `finish_job`, which is the one transaction of a job's results."""

import uuid
from datetime import UTC, datetime

from sqlalchemy import delete, func, select, update
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session, defer

from footprint.contracts.bounds import PROGRESS_NOTE_CHARS
from footprint.contracts.footprint import POINT_FIELDS
from footprint.service.db.models import (
    PENDING,
    REVISIONS,
    Footprint,
    FootprintPoint,
    Job,
    JobResult,
    Revision,
    Site,
    Trajectory,
    Vehicle,
    utc_now,
)

SUMMARY_FIELDS = ("area_nmi2", "max_crossrange_nmi", "max_downrange_nmi", "min_downrange_nmi", "trajectories")
ENTRY_FIELDS = ("latitude_deg", "longitude_deg", "heading_deg", "velocity_fps", "gamma_deg", "altitude_ft")


# ---------------------------------------------------------------------------------------- revisions
def revision(session: Session, *, name: str) -> int:
    """How many writes the stored `name`s (models.REVISIONS) have had."""
    return session.scalar(select(Revision.value).where(Revision.name == name)) or 0


def revisions(session: Session) -> dict[str, int]:
    """Every kind's revision (models.REVISIONS) in one query: {name: writes}."""
    return {name: int(value) for name, value in session.execute(select(Revision.name, Revision.value))}


def _changed(session: Session, name: str) -> None:
    """Count a write of `name`s, in the writer's transaction (a cached read of them is stale from its commit)."""
    assert name in REVISIONS, name
    session.execute(update(Revision).where(Revision.name == name).values(value=Revision.value + 1))


# --------------------------------------------------------------------------------------------- jobs
def create_job(session: Session, *, kind: str, study: dict, name: str | None) -> Job:
    """A queued job."""
    job = Job(
        id=str(uuid.uuid4()),
        kind=kind,
        name=name,
        status="queued",
        progress=0.0,
        study=study,
        attempts=0,
        created_at=utc_now(),
    )
    session.add(job)
    session.flush()
    return job


def get_job(session: Session, *, job_id: str) -> Job | None:
    """The job, or None."""
    return session.get(Job, job_id)


def list_jobs(session: Session, *, status: str | None, kind: str | None, limit: int, offset: int):
    """(jobs newest first, without their studies; total count) under the filters."""
    where = [c for c in (Job.status == status if status else None, Job.kind == kind if kind else None) if c is not None]
    total = session.scalar(select(func.count()).select_from(Job).where(*where))
    rows = session.scalars(
        select(Job)
        .options(defer(Job.study, raiseload=True))  # a list shows none (each a few kB of JSON)
        .where(*where)
        .order_by(Job.created_at.desc(), Job.id)
        .limit(limit)
        .offset(offset)
    ).all()
    return list(rows), int(total)


def pending_jobs(session: Session) -> list[Job]:
    """Queued and running jobs, oldest first (without their studies): the queue as the engine takes it."""
    query = select(Job).options(defer(Job.study, raiseload=True)).where(Job.status.in_(PENDING))
    return list(session.scalars(query.order_by(Job.created_at, Job.id)))


def measured_costs_s(session: Session, *, kinds: set[str], last: int) -> dict[str, tuple[float, int]]:
    """Each kind's median run time (started to finished) over its last `last` succeeded jobs, and how many."""
    costs = {}
    for kind in sorted(kinds):
        rows = session.execute(
            select(Job.started_at, Job.finished_at)
            .where(Job.kind == kind, Job.status == "succeeded", Job.started_at.is_not(None))
            .order_by(Job.finished_at.desc())
            .limit(last)
        ).all()
        times = sorted((f - s).total_seconds() for s, f in rows if f is not None)
        if times:
            costs[kind] = (times[len(times) // 2], len(times))
    return costs


def pending_job_ids(session: Session) -> list[str]:
    """Queued and running jobs, oldest first: what a restarted service submits again."""
    return list(session.scalars(select(Job.id).where(Job.status.in_(PENDING)).order_by(Job.created_at)))


def start_job(session: Session, *, job_id: str) -> Job | None:
    """Take a pending job for another attempt (it stays "queued" until a worker runs it: mark_running); None when
    it is no longer pending."""
    job = session.get(Job, job_id, with_for_update=True)
    if job is None or job.status not in PENDING:
        return None
    job.progress, job.progress_note, job.attempts = 0.0, None, job.attempts + 1
    return job


def mark_running(session: Session, *, job_id: str) -> None:
    """A worker has started the job's first task."""
    session.execute(
        update(Job)
        .where(Job.id == job_id, Job.status.in_(PENDING))
        .values(status="running", started_at=func.coalesce(Job.started_at, utc_now()))
    )


def set_progress(session: Session, *, job_id: str, progress: float, note: str | None = None) -> None:
    """Record the progress (0-1) of a running job, and what it is doing."""
    session.execute(
        update(Job)
        .where(Job.id == job_id, Job.status == "running")
        .values(progress=progress, progress_note=None if note is None else note[:PROGRESS_NOTE_CHARS])
    )


def fail_job(session: Session, *, job_id: str, error: str) -> None:
    """End a pending job as failed with a one-line error."""
    session.execute(
        update(Job)
        .where(Job.id == job_id, Job.status.in_(PENDING))
        .values(status="failed", error=error, finished_at=utc_now())
    )


def cancel_job(session: Session, *, job_id: str) -> Job | None:
    """Cancel a pending job (a finished one keeps its status); None for an unknown id."""
    job = session.get(Job, job_id, with_for_update=True)
    if job is not None and job.status in PENDING:
        job.status, job.finished_at = "cancelled", utc_now()
    return job


def job_result(session: Session, *, job_id: str) -> dict | None:
    """The stored result of a job, or None."""
    row = session.get(JobResult, job_id)
    return None if row is None else row.result


def finish_job(session: Session, *, job_id: str, result: dict, footprints: list[dict]) -> bool:
    """In one transaction: the job's result, its footprints and the status `succeeded`. False (nothing written)
    when the job is no longer running or its results exist already (the unique keys refuse a second write)."""
    try:
        with session.begin():
            job = session.get(Job, job_id, with_for_update=True)
            if job is None or job.status != "running":
                return False
            session.add(JobResult(job_id=job_id, result=result, created_at=utc_now()))
            taken: set[str] = set()
            for seq, record in enumerate(footprints):
                name = unique_name(session, record["name"], taken)
                taken.add(name)
                session.add(_footprint_row(job_id, seq, record | {"name": name}))
            if footprints:
                _changed(session, "footprints")
            job.status, job.progress, job.finished_at, job.error = "succeeded", 1.0, utc_now(), None
            job.progress_note = None
        return True
    except IntegrityError:
        return False


def unique_name(session: Session, name: str, taken=frozenset(), exclude_id: str | None = None) -> str:
    """`name`, or `name (2)`, `name (3)`... the first that no stored footprint (nor one of `taken`) has."""
    like = name.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_")
    rows = select(Footprint.name).where(Footprint.name.like(f"{like}%", escape="\\"))
    if exclude_id is not None:
        rows = rows.where(Footprint.id != exclude_id)
    used = set(session.scalars(rows)) | set(taken)
    candidate, n = name, 1
    while candidate in used:
        n += 1
        candidate = f"{name} ({n})"
    return candidate


def rename_footprint(session: Session, *, footprint_id: str, name: str) -> Footprint | None:
    """Give a footprint a new name (made unique as a job's are); None for an unknown id."""
    fp = session.get(Footprint, footprint_id)
    if fp is not None:
        fp.name = unique_name(session, name, exclude_id=footprint_id)
        _changed(session, "footprints")
    return fp


def _footprint_row(job_id: str, seq: int, record: dict) -> Footprint:
    fp = Footprint(
        id=str(uuid.uuid4()),
        job_id=job_id,
        seq=seq,
        name=record["name"],
        vehicle=record["vehicle"],
        method=record["method"],
        study=record["study"],
        created_at=utc_now(),
        **{k: record[k] for k in SUMMARY_FIELDS},
        **{f"entry_{k}": record["entry"][k] for k in ENTRY_FIELDS},
    )
    fp.points = [
        FootprintPoint(interior=interior, seq=i, **{k: p[k] for k in POINT_FIELDS})
        for interior, key in ((False, "points"), (True, "interior"))
        for i, p in enumerate(record[key])
    ]
    track = record["ground_track"]
    fp.ground_track = Trajectory(
        kind="zero_bank",
        summary=track["summary"],
        time_s=track["time_s"],
        latitude_deg=track["latitude_deg"],
        longitude_deg=track["longitude_deg"],
    )
    return fp


# --------------------------------------------------------------------------------------- footprints
def list_footprints(session: Session, *, job_id: str | None, limit: int, offset: int):
    """(footprints newest first, in job order within a job; total count)."""
    where = [Footprint.job_id == job_id] if job_id else []
    total = session.scalar(select(func.count()).select_from(Footprint).where(*where))
    rows = session.scalars(
        select(Footprint)
        .where(*where)
        .order_by(Footprint.created_at.desc(), Footprint.job_id, Footprint.seq)
        .limit(limit)
        .offset(offset)
    ).all()
    return list(rows), int(total)


def footprint_ids_of_job(session: Session, *, job_id: str) -> list[str]:
    """The job's footprints in job order."""
    return list(session.scalars(select(Footprint.id).where(Footprint.job_id == job_id).order_by(Footprint.seq)))


def get_footprint(session: Session, *, footprint_id: str) -> Footprint | None:
    """The footprint summary row, or None."""
    return session.get(Footprint, footprint_id)


def footprint_points(session: Session, *, footprint_id: str, interior: bool) -> list[FootprintPoint]:
    """The boundary (in order) or the interior points."""
    return list(
        session.scalars(
            select(FootprintPoint)
            .where(FootprintPoint.footprint_id == footprint_id, FootprintPoint.interior == interior)
            .order_by(FootprintPoint.seq)
        )
    )


def ground_track(session: Session, *, footprint_id: str) -> Trajectory | None:
    """The footprint's zero-bank ground track."""
    return session.scalar(select(Trajectory).where(Trajectory.footprint_id == footprint_id))


def delete_footprint(session: Session, *, footprint_id: str) -> bool:
    """Delete a footprint with its points and track; False for an unknown id."""
    fp = session.get(Footprint, footprint_id)
    if fp is None:
        return False
    session.delete(fp)
    _changed(session, "footprints")
    return True


def count_rows(session: Session, *, job_id: str) -> dict:
    """How many result rows a job has (job_results, footprints): each must be written once."""
    return {
        "job_results": session.scalar(select(func.count()).select_from(JobResult).where(JobResult.job_id == job_id)),
        "footprints": session.scalar(select(func.count()).select_from(Footprint).where(Footprint.job_id == job_id)),
    }


# ----------------------------------------------------------------------------------------- vehicles
def list_vehicles(session: Session) -> list[Vehicle]:
    """Stored custom vehicles by id."""
    return list(session.scalars(select(Vehicle).order_by(Vehicle.id)))


def get_vehicle(session: Session, *, vehicle_id: str) -> Vehicle | None:
    """A stored custom vehicle, or None."""
    return session.get(Vehicle, vehicle_id)


def create_vehicle(session: Session, *, vehicle_id: str, description: str, definition: dict, summary: dict) -> Vehicle:
    """Store a custom vehicle with its list item's numbers (the caller checks the id is free)."""
    row = Vehicle(id=vehicle_id, description=description, definition=definition, summary=summary, created_at=utc_now())
    session.add(row)
    session.flush()
    _changed(session, "vehicles")
    return row


def delete_vehicle(session: Session, *, vehicle_id: str) -> bool:
    """Delete a stored custom vehicle; False for an unknown id."""
    deleted = session.execute(delete(Vehicle).where(Vehicle.id == vehicle_id)).rowcount > 0
    if deleted:
        _changed(session, "vehicles")
    return deleted


# -------------------------------------------------------------------------------------------- sites
def list_sites(session: Session) -> list[Site]:
    """Every landing site, by id."""
    return list(session.scalars(select(Site).order_by(Site.id)))


def get_site(session: Session, *, site_id: int) -> Site | None:
    """A landing site, or None."""
    return session.get(Site, site_id)


def create_sites(session: Session, *, sites: list[dict]) -> list[Site]:
    """Store landing sites ({"name", "latitude_deg", "longitude_deg"} each)."""
    rows = [Site(created_at=utc_now(), **s) for s in sites]
    session.add_all(rows)
    session.flush()
    return rows


def upsert_sites(session: Session, *, sites: list[dict]) -> tuple[int, int]:
    """Store landing sites by name: a stored site of the same name takes the new place (and loses its verdict if it
    moved), another is added; a name given twice keeps its last place. (created, updated): the same CSV uploaded
    again duplicated every site (issue 53 item 5)."""
    given = {s["name"]: s for s in sites}
    stored = {r.name: r for r in session.scalars(select(Site).where(Site.name.in_(list(given))).order_by(Site.id))}
    updated = 0
    for name, site in given.items():
        row = stored.get(name)
        if row is not None:
            update_site(session, site_id=row.id, site=site)
            updated += 1
    create_sites(session, sites=[s for name, s in given.items() if name not in stored])
    return len(given) - updated, updated


def delete_sites(session: Session) -> int:
    """Delete every landing site: how many."""
    return session.execute(delete(Site)).rowcount


def store_verdicts(session: Session, *, verdicts: dict[int, dict]) -> None:
    """Each site's last reach verdict, by site id (sites deleted meanwhile are skipped)."""
    for site_id, verdict in verdicts.items():
        row = session.get(Site, site_id)
        if row is not None:
            row.last_reach = verdict


def update_site(session: Session, *, site_id: int, site: dict) -> Site | None:
    """Replace a site's fields; None for an unknown id. A site moved loses its reach verdict."""
    row = session.get(Site, site_id)
    if row is not None:
        if (row.latitude_deg, row.longitude_deg) != (site["latitude_deg"], site["longitude_deg"]):
            row.last_reach = None
        for k, v in site.items():
            setattr(row, k, v)
    return row


def delete_site(session: Session, *, site_id: int) -> bool:
    """Delete a landing site; False for an unknown id."""
    return session.execute(delete(Site).where(Site.id == site_id)).rowcount > 0


def iso(moment: datetime | None) -> str | None:
    """A stored time as ISO 8601 UTC (SQLite returns it without its zone)."""
    if moment is None:
        return None
    if moment.tzinfo is not None:
        moment = moment.astimezone(UTC)
    return moment.replace(tzinfo=None).isoformat(timespec="milliseconds") + "Z"

"""Jobs: submit (202), read, list, cancel, and progress as server-sent events."""

import asyncio

from fastapi import APIRouter, Depends, Query, Request, Response
from fastapi.responses import StreamingResponse
from starlette.concurrency import run_in_threadpool

from footprint import contracts
from footprint.contracts.records import strict_json
from footprint.service import deps, read_cache
from footprint.service.db import queries as q
from footprint.service.db.models import JOB_STATUSES, MAX_INTEGER, PENDING
from footprint.service.errors import ApiRoute, NotFound
from footprint.service.schemas import JobCreated, JobKind, JobList, JobRead, Queue, StoredId, job_create

router = APIRouter(tags=["jobs"], route_class=ApiRoute)
EVENT_POLL_S = 0.25  # how often the event stream looks at the job's row


def summary(job) -> dict:
    return {
        "id": job.id,
        "kind": job.kind,
        "name": job.name,
        "status": job.status,
        "progress": job.progress,
        "progress_note": job.progress_note,
        "error": job.error,
        "created_at": q.iso(job.created_at),
        "started_at": q.iso(job.started_at),
        "finished_at": q.iso(job.finished_at),
    }


def _read(session, job) -> dict:
    result = None
    if job.status == "succeeded":
        links = [f"/api/footprints/{i}" for i in q.footprint_ids_of_job(session, job_id=job.id)]
        result = {"footprints": links, **(q.job_result(session, job_id=job.id) or {})}
    return summary(job) | {"study": job.study, "result": result}


def submit_router() -> APIRouter:
    """POST /api/jobs for the kinds of job registered when the app is made: its body is one of their typed studies,
    validated by FastAPI with the HTTP door's context (deps.job_door)."""
    body_type = job_create()

    def create_job(body: body_type, request: Request, response: Response) -> dict:  # type: ignore[valid-type]
        """Check the study for its kind, store a queued job and hand it to the engine; 202 with the job's URL (also
        as the Location header) to poll or follow."""
        name = body.name or contracts.module(body.kind).WORK.default_name(body.study)
        with deps.sessions(request).begin() as session:
            job = q.create_job(session, kind=body.kind, study=contracts.stored_form(body.study), name=name)
            job_id = job.id
        deps.engine(request).submit(job_id=job_id, request=body.study)
        response.headers["Location"] = url = f"/api/jobs/{job_id}"
        return {"id": job_id, "name": name, "status": "queued", "url": url, "events": f"{url}/events"}

    submit = APIRouter(tags=["jobs"], route_class=ApiRoute)
    submit.add_api_route(
        "/jobs",
        create_job,
        methods=["POST"],
        response_model=JobCreated,
        status_code=202,
        dependencies=[Depends(deps.job_door)],
        responses={202: {"headers": {"Location": {"description": "the job's URL", "schema": {"type": "string"}}}}},
    )
    return submit


@router.get("/jobs", response_model=JobList)
async def list_jobs(
    request: Request,
    status: str | None = Query(None, pattern=f"^({'|'.join(JOB_STATUSES)})$"),
    kind: JobKind | None = Query(None),
    limit: int = Query(50, ge=1, le=500),
    offset: int = Query(0, ge=0, le=MAX_INTEGER),
) -> Response:
    """Jobs newest first, filtered by status and kind."""

    def build(session) -> read_cache.Serialized:
        jobs, total = q.list_jobs(session, status=status, kind=kind, limit=limit, offset=offset)
        return read_cache.as_json(JobList, {"items": [summary(j) for j in jobs], "total": total})

    return read_cache.plain(await deps.shared(request, ("jobs", status, kind, limit, offset), build))


QUEUE_COST_JOBS = 20  # a kind's cost: the median of its last 20 succeeded jobs' run times


@router.get("/queue", response_model=Queue)
async def queue(request: Request) -> dict:
    """The jobs not yet finished, oldest first as the engine takes them: each with the jobs ahead of it and an
    estimate of when it ends, from each kind's measured cost (the median run time of its last 20 succeeded jobs)
    shared over the cluster's workers; no estimate while a kind ahead has no measured cost (issue 53 item 2)."""
    status = deps.engine(request).recent_status()
    workers = max(int(status.get("workers") or 0), 1)

    def read(session) -> tuple[list[dict], dict]:
        pending = [summary(j) for j in q.pending_jobs(session)]
        return pending, q.measured_costs_s(session, kinds={j["kind"] for j in pending}, last=QUEUE_COST_JOBS)

    pending, costs = await deps.read(request, read)
    items, work_s = [], 0.0  # the work of the jobs so far, in worker-seconds
    for ahead, job in enumerate(pending):
        cost = costs.get(job["kind"])
        if work_s is not None and cost is not None:
            work_s += cost[0] * (1.0 - job["progress"])
        else:
            work_s = None  # unknown from here on
        items.append(job | {"ahead": ahead, "ends_in_s": None if work_s is None else work_s / workers})
    return {
        "workers": workers,
        "jobs": items,
        "costs": {k: {"median_s": c, "jobs": n} for k, (c, n) in costs.items()},
    }


@router.get("/jobs/{job_id}", response_model=JobRead, responses=read_cache.NOT_MODIFIED)
async def get_job(job_id: StoredId, request: Request) -> Response:
    """A job: status, progress, error, its study and its result links (with an ETag: If-None-Match answers 304 while
    it is unchanged)."""
    key = ("job", job_id)
    hit = await deps.cached_hit(request, key, "footprints")
    deps.answered(request, key, "footprints")
    if hit is not None:
        return read_cache.response(request, hit)
    cache = request.app.state.read_cache

    def load(session) -> read_cache.Serialized:
        revision = q.revision(session, name="footprints")
        job = q.get_job(session, job_id=job_id)
        if job is None:
            raise NotFound(f"no job {job_id!r}")
        answer = lambda: read_cache.as_json(JobRead, _read(session, job))  # noqa: E731
        # a job that has ended changes no more (every write of a job's row is to a pending one): its answer is kept
        # while its footprints' links are, i.e. until a footprint is written or deleted; a pending one is read anew,
        # once for the requests that wait together (deps.shared)
        return answer() if job.status in PENDING else cache.get(("footprints", *key), revision, answer)

    return read_cache.response(request, await deps.shared(request, key, load))


@router.delete("/jobs/{job_id}", response_model=JobRead)
def cancel_job(job_id: StoredId, request: Request) -> dict:
    """Cancel a queued or running job (a finished job keeps its status)."""
    with deps.sessions(request).begin() as session:
        job = q.cancel_job(session, job_id=job_id)
        if job is None:
            raise NotFound(f"no job {job_id!r}")
        cancelled = job.status == "cancelled"
    if cancelled:
        deps.engine(request).cancel(job_id=job_id)
    with deps.sessions(request).begin() as session:
        return _read(session, q.get_job(session, job_id=job_id))


def _state(request: Request, job_id: str) -> dict | None:
    with deps.sessions(request).begin() as session:
        job = q.get_job(session, job_id=job_id)
        return (
            None
            if job is None
            else {"id": job.id, "status": job.status, "progress": job.progress, "progress_note": job.progress_note}
        )


@router.get(
    "/jobs/{job_id}/events", response_class=StreamingResponse, responses={200: {"content": {"text/event-stream": {}}}}
)
async def job_events(job_id: StoredId, request: Request) -> StreamingResponse:
    """`event: progress` on every change of status or progress; `event: end` once the job is terminal."""
    if await run_in_threadpool(_state, request, job_id) is None:
        raise NotFound(f"no job {job_id!r}")

    async def stream():
        last = None
        while True:
            state = await run_in_threadpool(_state, request, job_id)
            if state is None:
                yield _event("end", {"id": job_id, "status": "deleted", "progress": 0.0})
                return
            if state != last:
                yield _event("progress", state)
                last = state
            if state["status"] not in PENDING:
                yield _event("end", state)
                return
            if await request.is_disconnected():
                return
            await asyncio.sleep(EVENT_POLL_S)

    return StreamingResponse(
        stream(), media_type="text/event-stream", headers={"Cache-Control": "no-cache", "X-Accel-Buffering": "no"}
    )


def _event(name: str, data: dict) -> str:
    return f"event: {name}\ndata: {strict_json(data)}\n\n"

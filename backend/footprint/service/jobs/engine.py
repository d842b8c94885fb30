"""The job engine: each job's tasks on Dask, its progress and results in the database.

One Dask client for the service's life: an in-process LocalCluster (processes, one thread each) or an external
scheduler, through footprint.parallel.start_client (the same code path as `footprint sweep`). A small thread pool
in the service process watches the jobs: it submits a job's parts (its contract's WORK.split, one Dask task each
through footprint.parallel.submit_parts), records progress as they report and complete, combines them
(WORK.combine, WORK.store) and writes the rows with the status `succeeded` in one transaction. It names no kind.
A restart submits queued and running jobs again; the unique keys on the results make a second write of the same
job impossible (so two service processes on one database may both compute a job, but only one stores it).

With several API processes (`footprint serve --api-processes N`) one engine runs beside them and polls the database
for the jobs they queue (JobEngine(polls=True)); each API process keeps only a RemoteJobs: the cluster's status.
A cancel is a job's row: every watcher looks at it each CANCEL_POLL_S, so a cancel through any process stops it.
"""

import logging
import re
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from contextlib import ExitStack

from sqlalchemy.orm import Session, sessionmaker

from footprint import contracts, parallel
from footprint.contracts.work import RunInfo
from footprint.service.db import queries as q
from footprint.service.db.models import PENDING
from footprint.service.settings import Settings

log = logging.getLogger("footprint.service.jobs")
MAX_ERROR_CHARS = 500  # a failed job's error line
# a Dask scheduler's, worker's or nanny's address (not the full stop or the quote that may end it)
CLUSTER_ADDRESS = re.compile(r"\b(?:tcp|tls|ucx|inproc|wss?)://[^\s'\"]*[^\s'\".,;:)]")
PROGRESS_WRITE_S = 1.0  # a running job's progress row is written at most this often
STOP_GRACE_S = 1.0  # a cancelled task still running after this (no report since: parallel.progress_reporter) has its
# worker restarted
STATUS_S = 1.0  # the cluster's status is asked of the scheduler at most this often (/api/health under load)
CANCEL_POLL_S = 1.0  # a running job's row is looked at this often for a cancel through another process
QUEUE_POLL_S = 0.2  # a polling engine looks for the jobs other processes queued this often
KEEP_POLL_S = 1.0  # the local cluster's size is looked at this often
REPLACE_AFTER_S = 10.0  # a worker missing this long (a nanny's restart takes seconds) is replaced
RESTART_TIMEOUT_S = 60.0  # a worker restart's wait for the nanny (a loaded machine starts a process slowly)


class NoWorkers(RuntimeError):
    """A queued job's cluster has had no worker for FOOTPRINT_NO_WORKERS_LIMIT_S."""


class JobTimeLimit(RuntimeError):
    """A job ran past FOOTPRINT_JOB_TIME_LIMIT_S."""


def one_line(exc: BaseException) -> str:
    """'Type: message' on one line, shortened to MAX_ERROR_CHARS. Anyone may read a job's error and /api/health: a
    database error keeps its driver's first line (never the SQL, its parameters or the link SQLAlchemy appends)
    and a cluster address becomes "<address>"."""
    from sqlalchemy.exc import StatementError

    message = str(exc.orig).partition("\n")[0] if isinstance(exc, StatementError) and exc.orig is not None else str(exc)
    text = " ".join(f"{type(exc).__name__}: {CLUSTER_ADDRESS.sub('<address>', message)}".split())
    return text if len(text) <= MAX_ERROR_CHARS else text[: MAX_ERROR_CHARS - 3] + "..."


class ClusterLink:
    """A Dask client of the service's cluster (footprint.parallel.start_client, the path `footprint sweep` takes:
    the configured scheduler, or a new LocalCluster) and the cluster's status for /api/health."""

    def __init__(self, *, settings: Settings):
        self._settings = settings
        self._stack = ExitStack()
        self._lock = threading.Lock()
        self._closing = threading.Event()
        self._status: tuple[float, dict] = (-STATUS_S, {})  # (when the scheduler was asked, what it said)
        self._asking = False  # a thread of recent_status() is asking the scheduler
        self.client = None
        self.most_workers = 0  # the most workers the scheduler has had: an external cluster's size
        self._workerless_since: float | None = None  # when the scheduler was first seen with no worker, since then

    def expected_workers(self) -> int:
        """The cluster's size: the local cluster's FOOTPRINT_DASK_WORKERS, else the most an external one has had."""
        return self.most_workers if self._settings.dask_scheduler else self._settings.dask_workers

    def _connect(self):
        """Not the default client: the service's threads pass it."""
        from footprint.parallel import start_client

        s = self._settings
        client, close = start_client(
            workers=s.dask_workers, scheduler=s.dask_scheduler or None, set_as_default=False, niceness=s.worker_niceness
        )
        self._stack.callback(close)
        return client

    def recent_status(self) -> dict | None:
        """The scheduler's last answer, at once (None before its first): when it is STATUS_S old, one thread asks
        again meanwhile. /api/health answers from it: asked in each request's turn, the once-a-second round trip
        to a busy scheduler held the readers that came at that moment past a second (issue 24 item 7)."""
        with self._lock:
            asked, last = self._status
            if time.monotonic() - asked >= STATUS_S and last and not self._asking:
                self._asking = True
                threading.Thread(target=self.status, name="footprint-cluster-status", daemon=True).start()
            return dict(last) if last else None

    def status(self) -> dict:
        """The cluster's health: ok (running, and no worker missing), scheduler address, workers and the size expected
        (as the scheduler said at most STATUS_S ago)."""
        with self._lock:
            asked, last = self._status
            if time.monotonic() - asked < STATUS_S:
                return dict(last)
        try:
            info = self.client.scheduler_info(n_workers=-1)
            workers = len(info.get("workers", {}))
            self.most_workers = max(self.most_workers, workers)
            with self._lock:
                self._workerless_since = None if workers else (self._workerless_since or time.monotonic())
            expected = self.expected_workers()
            now = {
                "ok": self.client.status == "running" and workers >= max(expected, 1),
                "scheduler": info.get("address", ""),
                "workers": workers,
                "expected_workers": expected,
            }
        except Exception as exc:  # noqa: BLE001 -- health reports, never raises
            now = {
                "ok": False,
                "scheduler": self._settings.dask_scheduler or "local",
                "workers": 0,
                "error": one_line(exc),
            }
        with self._lock:
            self._status, self._asking = (time.monotonic(), now), False
        return dict(now)

    def workerless_s(self) -> float:
        """How long the scheduler has had no worker, as last seen (0 while it has one)."""
        self.status()
        with self._lock:
            return 0.0 if self._workerless_since is None else time.monotonic() - self._workerless_since


class RemoteJobs(ClusterLink):
    """An API process's jobs when an engine in another process runs them (`footprint serve --api-processes N`): a
    job submitted is its queued row and a cancel its row marked, which that engine polls for; this process flies
    the synchronous trajectories itself."""

    def start(self) -> None:
        self.client = self._connect()
        threading.Thread(target=parallel.warm_numba, name="footprint-warm", daemon=True).start()

    def submit(self, *, job_id: str, request=None) -> None:
        """Nothing to do: the engine finds the queued row within QUEUE_POLL_S."""

    def cancel(self, *, job_id: str) -> None:
        """Nothing to do: the engine's watcher sees the cancelled row within CANCEL_POLL_S."""

    def close(self) -> None:
        self._closing.set()
        self._stack.close()


class JobEngine(ClusterLink):
    """Runs jobs on Dask and keeps their rows up to date; `polls`: also the jobs other processes queue."""

    def __init__(self, *, sessions: sessionmaker[Session], settings: Settings, polls: bool = False):
        super().__init__(settings=settings)
        self._sessions, self._polls = sessions, polls
        self._pool = ThreadPoolExecutor(settings.job_threads, thread_name_prefix="footprint-job")
        self._watched: set[str] = set()  # jobs submitted to the pool and not yet ended here
        self._futures: dict[str, list] = {}
        self._reports: dict[str, tuple[float, str]] = {}  # task key -> its last (progress, note) event
        self._started: dict[str, float] = {}  # task key -> when a worker started it (monotonic), from its first event
        self._wakes: dict[str, threading.Event] = {}  # task key -> its job's watcher, woken by each report
        self._cancels: set[str] = set()  # jobs cancelled through this process, not yet stopped
        self._restarting = threading.Lock()  # one restart at a time: a second one of a worker that is restarting
        # timed out, and the scheduler then removed the worker for good
        self.warm_seconds: float | None = None

    # ------------------------------------------------------------------------------------ lifetime
    def start(self) -> None:
        """Connect to (or start) the cluster, warm numba in its workers, and submit the pending jobs again."""
        self.client = self._connect()
        self.client.subscribe_topic(parallel.PROGRESS_TOPIC, self._on_report)
        threading.Thread(target=self._warm, name="footprint-warm", daemon=True).start()
        with self._sessions.begin() as session:
            pending = q.pending_job_ids(session)
        for job_id in pending:
            self.submit(job_id=job_id)
        if pending:
            log.info("resubmitted %d pending jobs", len(pending))
        if self._polls:
            threading.Thread(target=self._poll_queue, name="footprint-queue", daemon=True).start()
        if getattr(self.client, "cluster", None) is not None:  # our LocalCluster: kept at its size
            threading.Thread(target=self._keep_size, name="footprint-cluster", daemon=True).start()

    def _keep_size(self) -> None:
        """Replace the local cluster's workers that are missing for REPLACE_AFTER_S: a nanny whose restart failed
        (a loaded machine, a restart racing another) closes itself and its worker never comes back, and the queue
        would wait for ever."""
        missing_since: dict[str, float] = {}
        while not self._closing.wait(KEEP_POLL_S):
            try:
                cluster = self.client.cluster
                present = {w.get("name") for w in self.client.scheduler_info(n_workers=-1)["workers"].values()}
                now = time.monotonic()
                missing_since = {n: missing_since.get(n, now) for n in cluster.worker_spec if n not in present}
                overdue = [n for n, t in missing_since.items() if now - t >= REPLACE_AFTER_S]
                if overdue and not self._closing.is_set():
                    log.warning("replacing %d missing worker(s) of the local cluster", len(overdue))
                    cluster.sync(_replace_workers, cluster, overdue)
                    missing_since = {n: t for n, t in missing_since.items() if n not in overdue}
            except Exception as exc:  # noqa: BLE001 -- the next look tries again
                if not self._closing.is_set():
                    log.warning("could not check the cluster's workers: %s", one_line(exc))

    def _poll_queue(self) -> None:
        """Watch the jobs the API processes queue in the database."""
        while not self._closing.wait(QUEUE_POLL_S):
            try:
                with self._sessions.begin() as session:
                    pending = q.pending_job_ids(session)
            except Exception as exc:  # noqa: BLE001 -- a database that is away for a moment: look again later
                log.warning("could not read the job queue: %s", one_line(exc))
                continue
            for job_id in pending:
                self.submit(job_id=job_id)

    def _warm(self) -> None:
        t0 = time.perf_counter()
        try:
            self.client.run(parallel.warm_numba)
            parallel.warm_numba()  # this process flies the synchronous trajectories
            self.warm_seconds = time.perf_counter() - t0
            log.info("the workers' flight kernels are ready (%.0f s): jobs run at full speed", self.warm_seconds)
        except Exception as exc:  # noqa: BLE001 -- a cold cache only costs the first job time
            if not self._closing.is_set():
                log.warning("numba warm-up failed: %s", one_line(exc))

    def close(self) -> None:
        """Stop watching (pending jobs stay pending for the next start) and close the cluster."""
        self._closing.set()
        with self._lock:
            futures = [f for fs in self._futures.values() for f in fs]
        if self.client is not None and futures:
            self.client.cancel(futures)
        self._pool.shutdown(wait=True, cancel_futures=True)
        self._stack.close()

    # ---------------------------------------------------------------------------------------- jobs
    def submit(self, *, job_id: str, request=None) -> None:
        """Watch a queued job (its tasks go to Dask at once); `request`: its study as the router parsed it (a job
        submitted again after a restart is parsed from its row); a job watched here already is left alone."""
        with self._lock:
            if job_id in self._watched:
                return
            self._watched.add(job_id)
        self._pool.submit(self._run, job_id, request)

    def cancel(self, *, job_id: str) -> None:
        """Stop the job's tasks (its row is marked cancelled by the caller): its watcher stops them at once, the
        workers that run them restarted if need be (stop)."""
        with self._lock:
            futures = list(self._futures.get(job_id, ()))
            self._cancels.add(job_id)
            wakes = {self._wakes[f.key] for f in futures if f.key in self._wakes}
        for wake in wakes:
            wake.set()
        if not futures:
            with self._lock:
                self._cancels.discard(job_id)

    def stop(self, futures: list) -> None:
        """Cancel the futures (a running task stops at its next progress report: parallel.progress_reporter), and
        restart the workers still running one after STOP_GRACE_S: Dask cannot interrupt a running task, and a worker
        that kept computing a cancelled job would hold its core for hours. The workers are asked: the scheduler
        forgets a task at its cancel while the worker's thread runs on, and the next task waits behind it."""
        keys = {str(f.key) for f in futures}
        self.client.cancel(futures)
        deadline = time.monotonic() + STOP_GRACE_S
        while True:
            try:
                running = self.client.run(parallel.running_keys)
            except Exception as exc:  # noqa: BLE001 -- a worker lost meanwhile: its tasks are gone with it
                log.info("could not ask the workers what they run: %s", one_line(exc))
                return
            busy = [w for w, ks in running.items() if keys & set(ks)]
            if not busy or time.monotonic() >= deadline:
                break
            time.sleep(0.1)
        if busy:
            self._restart(busy, keys)

    def _restart(self, busy: list[str], keys: set[str]) -> None:
        """Restart the workers still running one of `keys`, one restart at a time (asked again once it is our turn:
        another stop may have restarted them meanwhile)."""
        with self._restarting:
            try:
                running = self.client.run(parallel.running_keys, workers=busy)
            except Exception as exc:  # noqa: BLE001 -- a worker lost meanwhile: its tasks are gone with it
                log.info("could not ask the workers what they run: %s", one_line(exc))
                return
            busy = [w for w, ks in running.items() if keys & set(ks)]
            if not busy:
                return
            log.info("restarting %d worker(s) to stop a cancelled or timed-out job", len(busy))
            try:
                self.client.restart_workers(busy, timeout=RESTART_TIMEOUT_S, raise_for_error=False)
            except Exception as exc:  # noqa: BLE001 -- a worker without a nanny cannot be restarted: say so
                log.warning("could not restart worker(s) %s: %s", busy, one_line(exc))

    def _run(self, job_id: str, request) -> None:
        try:
            with self._sessions.begin() as session:
                job = q.start_job(session, job_id=job_id)
                if job is None:
                    return
                kind, study, name = job.kind, job.study, job.name
            work = contracts.module(kind).WORK
            request = request or contracts.parse(kind, study)
            parts = list(work.split(request))
            t0 = time.perf_counter()
            outputs = self._compute(
                job_id, parallel.submit_parts(self.client, kind, request, parts, prefix=f"{kind}-{job_id}")
            )
            if outputs is None:
                return
            info = RunInfo(tasks=len(parts), workers=self.expected_workers(), seconds=time.perf_counter() - t0)
            stored = work.store(request, work.combine(request, outputs, info), name)
            with self._sessions() as session:
                written = q.finish_job(session, job_id=job_id, result=stored.result, footprints=stored.footprints)
            log.info("job %s %s", job_id, "succeeded" if written else "ended elsewhere (nothing written)")
        except Exception as exc:  # noqa: BLE001 -- a job that fails is that job's row, not the service's end
            if self._closing.is_set():
                return  # shutting down: the job stays pending and is submitted again on the next start
            log.info("job %s failed: %s", job_id, one_line(exc))
            with self._sessions.begin() as session:
                q.fail_job(session, job_id=job_id, error=one_line(exc))
        finally:
            with self._lock:
                self._futures.pop(job_id, None)
                self._watched.discard(job_id)

    def _compute(self, job_id: str, futures: list) -> list | None:
        """The outputs of the job's tasks in task order; None when the job was cancelled meanwhile."""
        index = {f.key: i for i, f in enumerate(futures)}
        with self._lock:
            self._futures[job_id] = futures
        outputs: list = [None] * len(futures)
        pending, done, written, last_write = list(futures), 0, (0.0, None), -PROGRESS_WRITE_S
        changed = threading.Event()  # a task ended or reported (or PROGRESS_WRITE_S passed)
        with self._lock:
            self._wakes.update((f.key, changed) for f in futures)
        for fut in futures:
            fut.add_done_callback(lambda _: changed.set())
        running, looked = False, time.monotonic()
        try:
            while pending:
                changed.wait(PROGRESS_WRITE_S)
                changed.clear()
                with self._lock:
                    cancelled = job_id in self._cancels
                    starts = [self._started[f.key] for f in futures if f.key in self._started]
                if not cancelled and time.monotonic() - looked >= CANCEL_POLL_S:  # through another process
                    cancelled, looked = self._cancelled(job_id), time.monotonic()
                if cancelled:
                    self.stop(futures)
                    return None
                if self.workerless_s() > self._settings.no_workers_limit_s:  # a queue it cannot run
                    self.stop(futures)
                    raise NoWorkers(
                        "the Dask scheduler has had no worker for "
                        f"{self._settings.no_workers_limit_s:g} s (FOOTPRINT_NO_WORKERS_LIMIT_S): start "
                        "workers on it and submit the job again"
                    )
                if starts and not running:  # "queued" until a worker really runs it
                    with self._sessions.begin() as session:
                        q.mark_running(session, job_id=job_id)
                    running = True
                if starts and time.monotonic() - min(starts) > self._settings.job_time_limit_s:
                    self.stop(futures)
                    raise JobTimeLimit(
                        f"the job ran past its time limit of {self._settings.job_time_limit_s:g} s "
                        "(FOOTPRINT_JOB_TIME_LIMIT_S) and was stopped"
                    )
                finished = [f for f in pending if f.done()]
                pending = [f for f in pending if not f.done()]
                for fut in finished:
                    if fut.status == "cancelled" or self._cancelled(job_id):
                        self.stop(futures)
                        return None
                    outputs[index[fut.key]] = fut.result()
                    fut.release()
                    done += 1
                progress, note = self._progress(futures, done)
                due = time.monotonic() - last_write >= PROGRESS_WRITE_S or written[1] is None
                if (progress, note) != written and progress >= written[0] and due:  # never backwards
                    with self._sessions.begin() as session:
                        q.set_progress(session, job_id=job_id, progress=progress, note=note)
                    written, last_write = (progress, note), time.monotonic()
        finally:
            with self._lock:
                self._cancels.discard(job_id)
                for f in futures:
                    self._reports.pop(f.key, None)
                    self._started.pop(f.key, None)
                    self._wakes.pop(f.key, None)
        return outputs

    def _on_report(self, event) -> None:
        """A task's progress event (client's event loop: kept, written by the job's own thread)."""
        _, msg = event
        with self._lock:
            self._started.setdefault(msg["key"], time.monotonic())
            if msg.get("note"):  # the first event only says the task started
                self._reports[msg["key"]] = (min(max(float(msg["progress"]), 0.0), 1.0), str(msg["note"]))
            wake = self._wakes.get(msg["key"])
        if wake is not None:
            wake.set()

    def _progress(self, futures: list, done: int) -> tuple[float, str | None]:
        """The job's progress: its finished tasks and what the running ones reported; the last note."""
        with self._lock:
            reports = [self._reports[f.key] for f in futures if f.key in self._reports and f.status == "pending"]
        note = reports[-1][1] if reports else None
        return (done + sum(p for p, _ in reports)) / len(futures), note

    def _cancelled(self, job_id: str) -> bool:
        """Cancelled (or deleted) in the database: by this process or another one over the same database."""
        with self._sessions.begin() as session:
            job = q.get_job(session, job_id=job_id)
            return job is None or job.status not in PENDING


async def _replace_workers(cluster, names: list[str]) -> None:
    """Close the cluster's missing workers' nannies (if any is left) and start new ones under the same names
    (SpecCluster._correct_state starts every worker of its spec that it does not hold)."""
    for name in names:
        nanny = cluster.workers.pop(name, None)
        if nanny is not None:
            try:
                await nanny.close()
            except Exception as exc:  # noqa: BLE001 -- a nanny already gone: its replacement starts all the same
                log.info("closing a lost nanny: %s", one_line(exc))
    await cluster._correct_state()

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

import contextlib
import functools
import logging
import math
import re
import threading
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

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
WATCH_S = 0.5  # the link looks at its scheduler this often (health's view, subscriptions, the local cluster's size)
ASK_TIMEOUT_S = 10.0  # a look whose question gets no answer in this long finds the scheduler not answering
STALE_S = 15.0  # health says "degraded" once the scheduler's last answer is this old (a hung scheduler; a killed one
# at once, its connection closed): at 5 s a machine at load 15 delayed the looks past it and health said degraded
LOST_SUBMITS = 1  # a job whose tasks are lost with their scheduler is submitted again this many times
DATABASE_RETRY_S = 1.0  # a job's start and outcome are written again this often while the database is away
CANCEL_POLL_S = 1.0  # a running job's row is looked at this often for a cancel through another process
QUEUE_POLL_S = 0.2  # a polling engine looks for the jobs other processes queued this often
RESTART_TIMEOUT_S = 60.0  # a worker restart's wait for the nanny (a loaded machine starts a process slowly)


class NoWorkers(RuntimeError):
    """A job's cluster could not run it (no scheduler answering, or no worker) for FOOTPRINT_NO_WORKERS_LIMIT_S."""


class ClusterLost(RuntimeError):
    """The job's tasks were lost with the Dask scheduler (killed, restarted or out of reach)."""


class DatabaseAway(RuntimeError):
    """The database did not answer before the service closed."""


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
    """A Dask client of the service's cluster (footprint.parallel.start_client, the path `footprint sweep` takes: the
    configured scheduler, or a new LocalCluster) kept alive by one watching thread, which every WATCH_S asks the
    scheduler who it is and which workers it has (the cluster's status for /api/health), builds a new client when
    Dask's own gave up reconnecting, renews the event subscriptions on every new connection (a restarted scheduler
    knows none of them: the jobs' progress never came again), says in the log why each worker left, and keeps a
    local cluster at its size (parallel.WorkerKeeper)."""

    def __init__(self, *, settings: Settings):
        self._settings = settings
        self._lock = threading.Lock()
        self._closing = threading.Event()
        self.client = None
        self._close_client: Callable[[], None] = lambda: None
        self._topics: dict[str, Callable] = {parallel.SCHEDULER_TOPIC: self._on_scheduler_event}  # renewed each link
        self._seen: tuple | None = None  # (client, its scheduler connection, the scheduler's id) of the last look
        self.generation = 0  # bumped at every new connection: tasks submitted before it are lost
        self.most_workers = 0  # the most workers the scheduler has had: an external cluster's size
        self._names: dict[str, str] = {}  # worker address -> name, for the log
        self._looked: tuple[float, dict] = (-math.inf, {})  # (when, the status) of the last look that got an answer
        self._runnable_at = time.monotonic()  # when a job could last run (a scheduler answering, a worker)
        self._down_since: float | None = None  # when the scheduler was first found not answering, since then
        self._keeper: parallel.WorkerKeeper | None = None

    # ------------------------------------------------------------------------------------ the link
    def start_link(self) -> None:
        """Connect (a scheduler that does not answer now is an error: the service does not start), look once (the
        subscriptions made before anything is submitted), and watch from a thread of its own."""
        self.client, self._close_client = self._connect()
        if getattr(self.client, "cluster", None) is not None:  # our LocalCluster: kept at its size
            self._keeper = parallel.WorkerKeeper(self.client.cluster)
        self._look()
        threading.Thread(target=self._watch, name="footprint-cluster", daemon=True).start()

    def close(self) -> None:
        self._closing.set()
        self._close_link()

    def _close_link(self) -> None:
        """The topics left, then the client closed: the scheduler logs a client's removal to its "all" topic, and
        wrote it to this very client, closed by then (a CRITICAL CommClosedError with its traceback at every stop)."""
        if self.client is not None and self.client.status == "running":
            for topic in self._topics:
                with contextlib.suppress(Exception):
                    self.client.unsubscribe_topic(topic)
        self._close_client()

    def expected_workers(self) -> int:
        """The cluster's size: the local cluster's FOOTPRINT_DASK_WORKERS, else the most an external one has had."""
        return self.most_workers if self._settings.dask_scheduler else self._settings.dask_workers

    def _connect(self):
        """Not the default client: the service's threads pass it."""
        s = self._settings
        return parallel.start_client(
            workers=s.dask_workers, scheduler=s.dask_scheduler or None, set_as_default=False, niceness=s.worker_niceness
        )

    def _watch(self) -> None:
        while not self._closing.wait(WATCH_S):
            try:
                self._look()
            except Exception as exc:  # noqa: BLE001 -- the watch never ends while the service runs
                if not self._closing.is_set():
                    log.warning("could not look at the Dask cluster: %s", one_line(exc))

    def _look(self) -> None:
        """One look: a new client if Dask's gave up, the scheduler asked, subscriptions renewed on a new connection,
        the status kept, the local cluster's missing workers replaced."""
        try:
            if self.client.status in ("closed", "closing") and not self._closing.is_set():
                self._reconnect()
            info = self.client.sync(self.client.scheduler.identity, n_workers=-1, callback_timeout=ASK_TIMEOUT_S)
            if self.client.status != "running":
                raise ConnectionError("the Dask client is connecting to its scheduler again")
        except Exception as exc:  # noqa: BLE001 -- a scheduler away: said by health, tried again at the next look
            self._not_answering(exc)
            return
        link = (self.client, self.client.scheduler_comm, info.get("id"))
        if not _same(link, self._seen):
            self._renew(link)
        workers = info.get("workers", {})
        self._names.update((address, str(w.get("name", address))) for address, w in workers.items())
        self.most_workers = max(self.most_workers, len(workers))
        now = time.monotonic()
        if workers:
            self._runnable_at = now
        with self._lock:
            down_since, self._down_since = self._down_since, None
            self._looked = (now, self._status_of(info.get("address", ""), len(workers)))
        if down_since is not None:
            log.warning("the Dask scheduler answers again, after %.0f s", now - down_since)
        if self._keeper is not None and not self._closing.is_set():
            self._keeper.look()

    def _reconnect(self) -> None:
        """A new client of the configured scheduler: Dask's own closes itself after trying for 10 s (start_client)."""
        old = self._close_client
        self.client, self._close_client = self._connect()
        old()

    def _renew(self, link: tuple) -> None:
        """A connection not seen before (the first, a reconnection, a new scheduler): its subscriptions made again
        (the scheduler keeps them per connection), and the tasks submitted before it counted lost (generation)."""
        for topic, handler in self._topics.items():
            self.client.subscribe_topic(topic, handler)
        if self._seen is not None:
            log.warning("a new connection to the Dask scheduler: subscriptions renewed, jobs in flight submitted again")
        self._seen = link
        self.generation += 1

    def _not_answering(self, exc: BaseException) -> None:
        with self._lock:
            first = self._down_since is None
            self._down_since = self._down_since or time.monotonic()
        if first and not self._closing.is_set():
            log.warning("the Dask scheduler does not answer: %s", one_line(exc))

    def _status_of(self, address: str, workers: int) -> dict:
        expected = self.expected_workers()
        status = {
            "ok": self.client.status == "running" and workers >= max(expected, 1),
            "scheduler": address,
            "workers": workers,
            "expected_workers": expected,
        }
        if not status["ok"]:
            status["error"] = f"{workers} of {expected} workers" if workers else "the scheduler has no worker"
        return status

    def _on_scheduler_event(self, event) -> None:
        """The scheduler's own events (its "all" topic): a worker that left, and why, in the log."""
        _, msg = event
        if isinstance(msg, dict) and msg.get("action") == "remove-worker":
            address = str(msg.get("worker", ""))
            log.warning("Dask worker %s left the cluster: %s", self._names.get(address, address),
                        parallel.why_a_worker_left(str(msg.get("stimulus_id", ""))))  # fmt: skip

    # ------------------------------------------------------------------------------- what it says
    def recent_status(self) -> dict:
        """The cluster's health as last looked at (at most WATCH_S old while the scheduler answers): ok when the
        client is connected, the scheduler answered within STALE_S and no worker is missing; else not ok, with why."""
        return self._state()[0]

    def unrunnable_s(self) -> float:
        """How long no job could have run (no scheduler answering, or no worker), as last looked at; 0 while one can."""
        status, answering = self._state()
        return 0.0 if answering and status["workers"] else time.monotonic() - self._runnable_at

    def _state(self) -> tuple[dict, bool]:
        """(the status, whether the scheduler answers now)."""
        with self._lock:
            looked_at, status = self._looked
            down_since = self._down_since
        status = dict(status) or {"ok": False, "scheduler": "", "workers": 0, "expected_workers": 0}
        now = time.monotonic()
        answering = self.client is not None and self.client.status == "running" and now - looked_at <= STALE_S
        if not answering:
            since = down_since if down_since is not None else looked_at if math.isfinite(looked_at) else now
            where = CLUSTER_ADDRESS.sub("<address>", self._settings.dask_scheduler) or "local"
            status.update(ok=False, error=f"no answer from the Dask scheduler ({where}) for {now - since:.0f} s")
        return status, answering


class RemoteJobs(ClusterLink):
    """An API process's jobs when an engine in another process runs them (`footprint serve --api-processes N`): a
    job submitted is its queued row and a cancel its row marked, which that engine polls for; this process flies
    the synchronous trajectories itself."""

    def start(self) -> None:
        self.start_link()

    def submit(self, *, job_id: str, request=None) -> None:
        """Nothing to do: the engine finds the queued row within QUEUE_POLL_S."""

    def cancel(self, *, job_id: str) -> None:
        """Nothing to do: the engine's watcher sees the cancelled row within CANCEL_POLL_S."""


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
        self._topics[parallel.PROGRESS_TOPIC] = self._on_report
        self.start_link()
        threading.Thread(target=self._warm, name="footprint-warm", daemon=True).start()
        with self._sessions.begin() as session:
            pending = q.pending_job_ids(session)
        for job_id in pending:
            self.submit(job_id=job_id)
        if pending:
            log.info("resubmitted %d pending jobs", len(pending))
        if self._polls:
            threading.Thread(target=self._poll_queue, name="footprint-queue", daemon=True).start()

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
            self.client.run(parallel.warm_numba_in_a_thread)
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
        self._close_link()

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
        try:
            self.client.cancel(futures)
        except Exception as exc:  # noqa: BLE001 -- a client without its scheduler: the tasks are gone with it
            log.info("could not cancel a job's tasks: %s", one_line(exc))
            return
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
            started = self._write(job_id, lambda session: _fields(q.start_job(session, job_id=job_id)))
            if started is None:
                return
            kind, study, name = started
            work = contracts.module(kind).WORK
            request = request or contracts.parse(kind, study)
            parts = list(work.split(request))
            t0 = time.perf_counter()
            outputs = self._outputs(job_id, kind, request, parts)
            if outputs is None:
                return
            info = RunInfo(tasks=len(parts), workers=self.expected_workers(), seconds=time.perf_counter() - t0)
            stored = work.store(request, work.combine(request, outputs, info), name)
            written = self._write(
                job_id,
                lambda s: q.finish_job(s, job_id=job_id, result=stored.result, footprints=stored.footprints),
                begins=False,
            )
            log.info("job %s %s", job_id, "succeeded" if written else "ended elsewhere (nothing written)")
        except Exception as exc:  # noqa: BLE001 -- a job that fails is that job's row, not the service's end
            if self._closing.is_set():
                return  # shutting down: the job stays pending and is submitted again on the next start
            error = one_line(exc)
            log.info("job %s failed: %s", job_id, error)
            try:
                self._write(job_id, functools.partial(q.fail_job, job_id=job_id, error=error))
            except DatabaseAway:  # the service closes meanwhile: the job stays pending for its next start
                pass
        finally:
            with self._lock:
                self._futures.pop(job_id, None)
                self._watched.discard(job_id)

    def _outputs(self, job_id: str, kind: str, request, parts: list) -> list | None:
        """The outputs of the job's parts, computed on the cluster once it can take them; submitted once more when the
        cluster is lost under them (its scheduler killed or restarted), a job lost twice failing with one line; None
        when the job was cancelled, or the service closes, meanwhile."""
        for attempt in range(LOST_SUBMITS + 1):
            generation = self._wait_for_link(job_id)
            if generation is None:
                return None
            futures = parallel.submit_parts(self.client, kind, request, parts, prefix=f"{kind}-{job_id}")
            try:
                return self._compute(job_id, futures, generation)
            except ClusterLost as exc:
                if attempt == LOST_SUBMITS:
                    raise ClusterLost(f"{exc}, {attempt + 1} times: submit the job again") from None
                log.warning("job %s: %s; submitted again once the cluster answers", job_id, exc)
        return None  # not reached: the last attempt returns or raises

    def _wait_for_link(self, job_id: str) -> int | None:
        """The link's generation once a job's tasks can go to the cluster (a client connected, its subscriptions
        made); None when the job is cancelled or the service closes meanwhile; NoWorkers past the limit."""
        while not self._linked():
            if self._closing.is_set() or self._cancelled(job_id):
                return None
            self._check_runnable()
            time.sleep(WATCH_S)
        return self.generation

    def _linked(self) -> bool:
        """The client is connected and the watch has renewed its subscriptions on this connection."""
        client, seen = self.client, self._seen
        return client.status == "running" and seen is not None and _same((client, client.scheduler_comm), seen[:2])

    def _check_runnable(self) -> None:
        """NoWorkers, saying why, once no job could have run for FOOTPRINT_NO_WORKERS_LIMIT_S."""
        limit = self._settings.no_workers_limit_s
        if self.unrunnable_s() > limit:
            status, answering = self._state()
            what = "had no worker" if answering else "not answered"
            raise NoWorkers(
                f"the Dask scheduler has {what} for {limit:g} s (FOOTPRINT_NO_WORKERS_LIMIT_S): "
                f"{'start workers on it' if answering else 'start it'} and submit the job again"
            )

    def _compute(self, job_id: str, futures: list, generation: int) -> list | None:
        """The outputs of the job's tasks in task order; None when the job was cancelled meanwhile; ClusterLost when the
        link's generation moves on under them (the tasks are gone with their scheduler)."""
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
                if self.generation != generation:
                    raise ClusterLost("the job's tasks were lost with the Dask scheduler (killed or restarted)")
                try:
                    self._check_runnable()  # a queue it cannot run
                except NoWorkers:
                    self.stop(futures)
                    raise
                finished = [f for f in pending if f.done()]
                pending = [f for f in pending if not f.done()]
                if (starts or finished) and not running:  # "queued" until a worker really runs it
                    running = self._try(functools.partial(q.mark_running, job_id=job_id))[0]
                if starts and time.monotonic() - min(starts) > self._settings.job_time_limit_s:
                    self.stop(futures)
                    raise JobTimeLimit(
                        f"the job ran past its time limit of {self._settings.job_time_limit_s:g} s "
                        "(FOOTPRINT_JOB_TIME_LIMIT_S) and was stopped"
                    )
                for fut in finished:
                    if self._cancelled(job_id):
                        self.stop(futures)
                        return None
                    if fut.status == "cancelled":  # not by us: by Dask's client, which lost its scheduler
                        raise ClusterLost("the job's tasks were lost with the Dask scheduler (killed or restarted)")
                    outputs[index[fut.key]] = fut.result()
                    fut.release()
                    done += 1
                progress, note = self._progress(futures, done)
                due = time.monotonic() - last_write >= PROGRESS_WRITE_S or written[1] is None
                if (progress, note) != written and progress >= written[0] and due:  # never backwards
                    if self._try(functools.partial(q.set_progress, job_id=job_id, progress=progress, note=note))[0]:
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
        """Cancelled (or deleted) in the database: by this process or another one over the same database (not known
        while the database is away: running on)."""
        read, status = self._try(lambda s: _fields(q.get_job(s, job_id=job_id), "status"))
        return read and (status is None or status[0] not in PENDING)

    def _write(self, job_id: str, act: Callable[[Session], Any], *, begins: bool = True) -> Any:
        """act(session) in one transaction (its own when not `begins`), tried again every DATABASE_RETRY_S while the
        database is away (restarted, its connections dropped: not the job's failure), so that a job's start and
        outcome are written once it is back; DatabaseAway if the service closes meanwhile."""
        warned = False
        while True:
            written, value = self._try(act, begins=begins)
            if written:
                return value
            if self._closing.is_set():
                raise DatabaseAway("the database did not answer before the service closed")
            if not warned:
                log.warning("job %s: the database does not answer; its rows are written once it does", job_id)
                warned = True
            self._closing.wait(DATABASE_RETRY_S)

    def _try(self, act: Callable[[Session], Any], *, begins: bool = True) -> tuple[bool, Any]:
        """(True, act(session)) in one transaction; (False, None) when the database is away (a progress note
        skipped, a cancel looked for at the next poll)."""
        try:
            with self._sessions() as session:
                if not begins:
                    return True, act(session)
                with session.begin():
                    return True, act(session)
        except Exception as exc:
            if _database_away(exc):
                return False, None
            raise


def _fields(job, *names: str) -> tuple | None:
    """The job row's fields read inside its transaction (kind, study and name by default); None without a row."""
    return None if job is None else tuple(getattr(job, n) for n in names or ("kind", "study", "name"))


def _database_away(exc: BaseException) -> bool:
    """The database did not answer (its server restarted or unreachable, SQLite's lock held past its timeout)."""
    from sqlalchemy.exc import DBAPIError, InterfaceError, OperationalError

    return isinstance(exc, OperationalError | InterfaceError) or (
        isinstance(exc, DBAPIError) and exc.connection_invalidated
    )


def _same(link: tuple, seen: tuple | None) -> bool:
    """The same client, connection and scheduler (each the same object, or the same id)."""
    return seen is not None and all(a is b or a == b for a, b in zip(link, seen, strict=True))

"""The one runner of every kind of work (footprint.contracts.work) and the package's only Dask code: a kind's parts
run in this process, or as Dask tasks on a LocalCluster of worker processes or an external scheduler; the CLI, the
Python API and the service's job engine all run work through here. The core starts no processes: its parallel
loops take the map-like callable `client_map` gives.

A part's task carries the contract module's name, the request as JSON and the part; each worker parses a request
once (kept for the request's other parts) and reports progress as Dask events that the job engine follows; a task
whose future is cancelled stops at its next report.
"""

import asyncio
import concurrent.futures
import importlib
import json
import logging
import os
import signal
import threading
import time
import uuid
from collections import OrderedDict
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from types import ModuleType
from typing import Any

from footprint import contracts
from footprint.contracts.work import OnProgress, RunInfo, Work

Progress = Callable[[int, int], None]  # progress(parts done, parts) after each part
PROGRESS_TOPIC = "footprint-progress"  # the Dask event topic of the tasks' progress (the job engine subscribes)
SCHEDULER_TOPIC = "all"  # the scheduler's own events: a worker added or removed, and why (stimulus_id)
KEEP_S = 1.0  # a kept cluster's size is looked at this often
REPLACE_AFTER_S = 10.0  # a worker missing this long, its nanny closed or its process ended, is replaced
START_GRACE_S = 180.0  # a worker whose nanny is still starting its process is given this long (a loaded machine)
LOST_WORKER_TIMEOUT = "distributed.deploy.lost-worker-timeout"
PROGRESS_EVERY_S = 0.5  # a task's progress events at most this often
log = logging.getLogger("footprint.parallel")
PARSED_KEPT = 4  # requests a worker keeps parsed (one job's parts share one parse)
WARM_CASE = {
    "vehicle": {"builtin": "lod-2.2"},
    "entry": {"altitude_ft": 364_800, "velocity_fps": 24_480, "gamma_deg": -2.0},
    "stop": {"altitude_ft": 250_000},
}  # a short flight that loads every compiled kernel of an open-loop flight
WARM_GUIDED_CASE = WARM_CASE | {
    "bank": {
        "law": "guided",
        "target": {"latitude_deg": 0.0, "longitude_deg": 60.0},
        "terminal": {"altitude_ft": 80_000, "velocity_fps": 2_500},
    }
}  # and the guidance's: compiled in a synchronous request, they took 18 s of its 10 s limit (CI of 2026-12-07)
# Dask's nanny starts each worker with glibc's MALLOC_TRIM_THRESHOLD_=65536, which also fixes glibc's mmap threshold:
# every flight's arrays of over 128 kB (its rows) were then new pages from the kernel, and a worker flew a dispersion
# chunk ~8 % slower than this process (a process started with it: 3.39-3.44 s against 3.15-3.16 s for five chunks)
NANNY_MALLOC_TRIM = "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_"


# ----------------------------------------------------------------------------------------------- the runner
def run(
    kind: str,
    request: Any,
    progress: Progress | None = None,
    *,
    on_progress: OnProgress | None = None,
    client: Any = None,
    workers: int | None = None,
    scheduler: str | None = None,
) -> Any:
    """The kind's answer (its contract's WORK.combine) for a request (a dict or a parsed model): in this process,
    or on Dask when a `client`, a count of local `workers` or a `scheduler` address is given. progress(done, total)
    after each part; on_progress(fraction, note) inside a part run in this process (True from it stops the part).
    Raises ValidationError or InputError for a bad request before any work starts."""
    work = contracts.module(kind).WORK
    request = contracts.parse(kind, request)
    parts = list(work.split(request))
    if client is None and workers is None and scheduler is None:
        return work.combine(request, *_run_here(work, request, parts, progress, on_progress))
    warm_s = warm_numba()  # numba's on-disk cache written here before the workers load it
    t0 = time.perf_counter()
    with dask_client(client, workers=workers, scheduler=scheduler) as c:
        started = time.perf_counter()
        n_workers = worker_count(c)
        futures = submit_parts(c, kind, request, parts, prefix=kind)
        outputs = gather(c, futures, progress)
        finished = time.perf_counter()
    return work.combine(
        request,
        outputs,
        RunInfo(
            tasks=len(parts),
            workers=n_workers,
            seconds=finished - started,
            startup_seconds=started - t0,
            warm_seconds=warm_s,
        ),
    )


def _run_here(
    work: Work, request: Any, parts: Sequence[Any], progress: Progress | None, on_progress: OnProgress | None
) -> tuple[list[Any], RunInfo]:
    t0 = time.perf_counter()
    outputs = []
    if progress:
        progress(0, len(parts))
    for done, part in enumerate(parts, 1):
        outputs.append(work.run_part(request, part, on_progress))
        if progress:
            progress(done, len(parts))
    return outputs, RunInfo(tasks=len(parts), seconds=time.perf_counter() - t0)


def submit_parts(client: Any, kind: str, request: Any, parts: Sequence[Any], *, prefix: str) -> list[Any]:
    """One Dask task per part, keyed "<prefix>-<token>-<i>" (each run's keys its own): its future, in part order."""
    module_name, data = contracts.MODULES[kind], json.dumps(contracts.stored_form(request))
    token = uuid.uuid4().hex[:8]
    return [
        client.submit(part_task, module_name, data, part, key=f"{prefix}-{token}-{i}", pure=False)
        for i, part in enumerate(parts)
    ]


def gather(client: Any, futures: list[Any], progress: Progress | None = None) -> list[Any]:
    """The futures' results in their order, taken as they complete (each released once read)."""
    from distributed import as_completed

    index = {f.key: i for i, f in enumerate(futures)}
    outputs: list[Any] = [None] * len(futures)
    if progress:
        progress(0, len(futures))
    for done, fut in enumerate(as_completed(futures), 1):
        outputs[index[fut.key]] = fut.result()
        fut.release()
        if progress:
            progress(done, len(futures))
    return outputs


# ------------------------------------------------------------------------------------------ in the worker
_PARSED: OrderedDict[tuple[str, str], Any] = OrderedDict()


def part_task(module_name: str, data: str, part: Any) -> Any:
    """A Dask task: one part of a request (the contract module's WORK.run_part), its progress reported."""
    module = importlib.import_module(module_name)
    return module.WORK.run_part(parsed(module, data), part, progress_reporter())


def parsed(module: ModuleType, data: str) -> Any:
    """The request of `data` (JSON), parsed by its contract module once in this process."""
    key = (module.__name__, data)
    if key in _PARSED:
        _PARSED.move_to_end(key)
    else:
        _PARSED[key] = module.parse_request(json.loads(data))
        while len(_PARSED) > PARSED_KEPT:
            _PARSED.popitem(last=False)
    return _PARSED[key]


def progress_reporter() -> OnProgress | None:
    """on_progress(fraction, note) for the core's long loops, sent as a Dask event of this task (its key), at
    most every PROGRESS_EVERY_S; None outside a Dask worker. Returns True once the task is cancelled (the engine's
    cancel and time limit cancel its future: the worker marks the running task), which stops the loop at its next
    report: the worker is free at once, not restarted (the engine's last resort). Its creation sends the task's
    first event, which tells the engine a worker has started it (the job is "running", its time limit counts)."""
    from distributed import get_worker

    try:
        worker = get_worker()
    except ValueError:
        return None
    key, last = worker.get_current_task(), [0.0]
    worker.log_event(PROGRESS_TOPIC, {"key": str(key), "progress": 0.0, "note": ""})

    def on_progress(fraction: float, note: str) -> bool:
        now = time.monotonic()
        if now - last[0] >= PROGRESS_EVERY_S:
            last[0] = now
            worker.log_event(PROGRESS_TOPIC, {"key": str(key), "progress": float(fraction), "note": note})
        task = worker.state.tasks.get(key)  # read in this thread, written by the worker's event loop: a plain lookup
        return task is None or task.state in ("cancelled", "released", "forgotten")

    return on_progress


def running_keys(dask_worker: Any) -> list[str]:
    """The keys this worker's threads run now, cancelled ones included (client.run(running_keys))."""
    return [str(task.key) for task in dask_worker.state.executing]


def warm_numba() -> float:
    """Fly two short trajectories, open-loop and guided, so this process has loaded (or compiled) numba's cache;
    the seconds taken."""
    t0 = time.perf_counter()
    for case in (WARM_CASE, WARM_GUIDED_CASE):
        run("case", case)
    return time.perf_counter() - t0


def warm_worker() -> None:
    """Every kind's contract module imported (SciPy's stats, CasADi) and numba's cache loaded: what a worker's first
    task of any kind would otherwise do first."""
    for name in contracts.MODULES.values():
        importlib.import_module(name)
    warm_numba()


async def warm_numba_in_a_thread() -> float:
    """warm_numba() for client.run: a plain function runs on the worker's event loop, whose heartbeats and connection
    it holds meanwhile (a cold cache on a loaded machine compiled for minutes, and the worker did not see its scheduler
    go away); a coroutine function is awaited there, and this one compiles in a thread."""
    return await asyncio.to_thread(warm_numba)


# ------------------------------------------------------------------------------------------ the cluster
def default_workers() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def start_client(
    *, workers: int | None = None, scheduler: str | None = None, set_as_default: bool = True, niceness: int = 0
) -> tuple[Any, Callable[[], None]]:
    """(client, close): a client of `scheduler` ("tcp://host:port"), or of a new LocalCluster of `workers` processes
    (default: the cores), one thread each, no dashboard (its HTTP routes on any free port), each at `niceness` (the
    service's readers go first). close() shuts them from any thread (their context managers bind a context variable
    to the thread that entered them; the service starts and stops in different threads)."""
    import dask
    from distributed import Client, LocalCluster

    if scheduler is not None:
        client = Client(scheduler, timeout="10s", set_as_default=set_as_default)
        return client, client.close
    # ":0": any free port for the scheduler's HTTP routes (None would still take 8787, or warn when it is taken)
    with dask.config.set({NANNY_MALLOC_TRIM: None}):
        cluster = LocalCluster(
            n_workers=workers or default_workers(),
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            scheduler_kwargs={"dashboard": False},
            silence_logs=logging.ERROR,
        )
    client = Client(cluster, set_as_default=set_as_default)
    client.register_plugin(_worker_plugin(ParentStops))  # every worker, and each one that replaces a worker later
    if niceness:
        client.register_plugin(_worker_plugin(Niceness, niceness))
    client.register_plugin(_worker_plugin(Warm))  # after Niceness: at its priority

    def close() -> None:
        client.close()
        cluster.close()

    return client, close


@contextmanager
def dask_client(client: Any = None, *, workers: int | None = None, scheduler: str | None = None) -> Iterator[Any]:
    """The client to submit to: the one given, else start_client's, closed on exit."""
    if client is not None:
        yield client
        return
    started, close = start_client(workers=workers, scheduler=scheduler)
    try:
        yield started
    finally:
        close()


def client_map(client: Any) -> Callable[..., list[Any]]:
    """A callable with builtin map's signature that runs func on the client's workers, one task per item, and
    returns the results in order. func must be picklable (defined at module level); pure=False: each item is
    run, none taken for another's result by its arguments' hash."""

    def map_tasks(func: Callable[..., Any], *iterables: Any) -> list[Any]:
        results: list[Any] = client.gather(client.map(func, *iterables, pure=False))
        return results

    return map_tasks


def worker_count(client: Any) -> int:
    """How many workers the client's scheduler has now."""
    return len(client.scheduler_info(n_workers=-1)["workers"])


# ------------------------------------------------------------------------- a local cluster kept at its size
# why the scheduler removed a worker, by the start of its stimulus id (distributed.scheduler.remove_worker's callers)
WHY_A_WORKER_LEFT = {
    "handle-worker-cleanup": "its connection closed (its process ended or was killed)",
    "check-worker-ttl": "it missed its heartbeats past distributed.scheduler.worker-ttl (a stalled process)",
    "worker-send-comm-fail": "the scheduler could not reach it",
    "send-all-comm-fail": "the scheduler could not reach it",
    "worker-clos": "it closed itself",
    "nanny-close": "its nanny closed it",
    "retire-workers": "it was retired",
    "restart": "it was restarted on request (a cancelled or timed-out job's task)",
}


def why_a_worker_left(stimulus_id: str) -> str:
    """A worker's removal in words, from the scheduler's stimulus id."""
    for start, words in WHY_A_WORKER_LEFT.items():
        if stimulus_id.startswith(start) or f"-{start}" in stimulus_id:
            return words
    return f"the scheduler's reason: {stimulus_id or 'none given'}"


class WorkerKeeper:
    """Keeps a LocalCluster at the size of its spec. A worker the scheduler does not have while its nanny lives (a
    restart, a process killed and started again) is the nanny's to bring back, given START_GRACE_S: a start on a
    loaded machine is slow, and a replacement would only start over. A worker whose nanny is gone or closed (a restart
    that failed closes it) gets a new nanny under its name after REPLACE_AFTER_S. look() is one look, from any thread
    but the cluster's loop; a replacement runs on that loop, and the next one waits for it."""

    def __init__(self, cluster: Any):
        import dask

        self.cluster = cluster
        self._missing_since: dict[Any, float] = {}
        self._replacing: concurrent.futures.Future[None] | None = None
        # SpecCluster closes the nanny of a worker the scheduler has not had back for this long (read when one is
        # lost, so set for the process): 15 s by default, which cut short every restart slower than that on a
        # loaded machine (a cancel's restart took 20 s), and its worker never came back (issue 49 item 6)
        dask.config.set({LOST_WORKER_TIMEOUT: f"{START_GRACE_S:g}s"})

    def look(self) -> list[Any]:
        """The names of the workers whose replacement starts now."""
        if self._replacing is not None and not self._replacing.done():
            return []
        present = {str(w.get("name")) for w in self.cluster.scheduler_info.get("workers", {}).values()}
        now = time.monotonic()
        missing = [n for n in self.cluster.worker_spec if str(n) not in present]
        self._missing_since = {n: self._missing_since.get(n, now) for n in missing}
        overdue = [n for n, t in self._missing_since.items() if now - t >= self._grace_s(n)]
        if overdue:
            log.warning("replacing %d worker(s) of the local cluster missing for %.0f s or more: %s", len(overdue),
                        min(now - self._missing_since[n] for n in overdue), ", ".join(map(str, overdue)))  # fmt: skip
            loop = self.cluster.loop.asyncio_loop
            self._replacing = asyncio.run_coroutine_threadsafe(_replace_workers(self.cluster, overdue), loop)
            for n in overdue:
                self._missing_since.pop(n, None)
        return overdue

    def _grace_s(self, name: Any) -> float:
        nanny = self.cluster.workers.get(name)
        alive = nanny is not None and getattr(nanny.status, "name", "") in ("init", "starting", "running")
        return START_GRACE_S if alive else REPLACE_AFTER_S


async def _replace_workers(cluster: Any, names: list[Any]) -> None:
    """Close the cluster's missing workers' nannies (if any is left) and start new ones under the same names
    (SpecCluster._correct_state starts every worker of its spec that it does not hold)."""
    for name in names:
        nanny = cluster.workers.pop(name, None)
        if nanny is not None:
            try:
                await nanny.close()
            except Exception as exc:  # noqa: BLE001 -- a nanny already gone: its replacement starts all the same
                log.info("closing a lost nanny: %s", exc)
    try:
        await cluster._correct_state()
    except Exception as exc:  # noqa: BLE001 -- a start that failed: the next look tries again
        log.warning("could not start a worker of the local cluster: %s", exc)


@contextmanager
def kept_at_size(cluster: Any) -> Iterator[WorkerKeeper]:
    """A thread that keeps `cluster` at its size (WorkerKeeper) while the context lasts: for a LocalCluster that no
    job engine watches (the tests' shared cluster)."""
    keeper, stopped = WorkerKeeper(cluster), threading.Event()

    def keep() -> None:
        while not stopped.wait(KEEP_S):
            try:
                keeper.look()
            except Exception as exc:  # noqa: BLE001 -- the next look tries again
                log.warning("could not keep the cluster's workers: %s", exc)

    thread = threading.Thread(target=keep, name="footprint-keeper", daemon=True)
    thread.start()
    try:
        yield keeper
    finally:
        stopped.set()
        thread.join()


# -------------------------------------------------------------------- the local cluster's worker processes
class Niceness:
    """Every thread of the worker's process at `niceness` or nicer (a flight can wait a few milliseconds, a reader of
    the map cannot: issue 24 item 7). On Linux setpriority(2) sets one thread's value and a new thread inherits its
    creator's, so the executor thread that flies the tasks (and any thread it starts) runs at it."""

    name = "footprint-niceness"
    idempotent = True

    def __init__(self, niceness: int):
        self.niceness = niceness

    def setup(self, worker: Any) -> None:
        for tid in _threads():
            try:
                os.setpriority(os.PRIO_PROCESS, tid, max(self.niceness, os.getpriority(os.PRIO_PROCESS, tid)))
            except OSError:  # a thread gone meanwhile: the others still go
                pass


class Warm:
    """warm_worker() as the worker starts, not in its first task: a fresh worker's first dispersion chunk took 2.1 s
    against 0.8 s for the next (the imports and numba's cache). register_plugin returns when every worker has done
    it, so a new cluster's first run, and a warm-up run on one worker, find them all ready."""

    name = "footprint-warm"
    idempotent = True

    async def setup(self, worker: Any) -> None:
        await asyncio.to_thread(warm_worker)  # off the worker's event loop: its heartbeats go on meanwhile


class ParentStops:
    """SIGINT ignored in the worker's process (its main thread runs the worker's event loop, where setup is called):
    the service that started the cluster stops it, and each worker's own KeyboardInterrupt printed a 30-line
    traceback over the shutdown (issue 25 item 8). And the heartbeat a closing worker had in flight, cut off when it
    closes its own connections, is not reported as an error (a 40-line traceback on a loaded machine's Ctrl+C)."""

    name = "footprint-parent-stops"
    idempotent = True

    def setup(self, worker: Any) -> None:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        logging.getLogger("distributed.worker").addFilter(ClosingHeartbeat(worker))


class ClosingHeartbeat(logging.Filter):
    """Drops distributed's "Failed to communicate with scheduler during heartbeat" once `worker` is closing
    (Worker.close closes its connection pool under the heartbeat it may be awaiting); kept while it runs."""

    CLOSING = ("closing", "closing_gracefully", "closed")  # distributed.core.Status names

    def __init__(self, worker: Any):
        super().__init__()
        self.worker = worker

    def filter(self, record: logging.LogRecord) -> bool:
        closing = getattr(self.worker.status, "name", "") in self.CLOSING
        return not (closing and str(record.msg).startswith("Failed to communicate with scheduler during heartbeat"))


def _worker_plugin(behaviour: type, *args: Any) -> Any:
    """A distributed WorkerPlugin (each worker, and every one that replaces a worker later) doing `behaviour`'s setup
    (made here: Dask is imported only when a cluster starts)."""
    from distributed.diagnostics.plugin import WorkerPlugin

    return type(behaviour.__name__, (behaviour, WorkerPlugin), {})(*args)


def _threads() -> list[int]:
    """This process's thread ids (0, the calling thread, where /proc does not list them)."""
    try:
        return [int(t) for t in os.listdir("/proc/self/task")]
    except OSError:
        return [0]

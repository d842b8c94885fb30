"""The package's one Dask client path, outside the numerical core: a LocalCluster of worker processes by
default or a client of an external scheduler, and the map-like callable the core's parallel loops take
(footprint.core.constrained's `map_tasks`), so the core itself starts no processes."""

import logging
import os
from contextlib import contextmanager


def default_workers() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def start_client(*, workers: int | None = None, scheduler: str | None = None, set_as_default: bool = True,
                 niceness: int = 0):
    """(client, close): a client of `scheduler` ("tcp://host:port"), or of a new LocalCluster of `workers` processes
    (default: the cores), one thread each, no dashboard (its HTTP routes on any free port), each at `niceness` (the
    service's readers go first). close() shuts them from any thread (their context managers bind a context variable
    to the thread that entered them; the service starts and stops in different threads)."""
    from distributed import Client, LocalCluster

    if scheduler is not None:
        client = Client(scheduler, timeout="10s", set_as_default=set_as_default)
        return client, client.close
    # ":0": any free port for the scheduler's HTTP routes (None would still take 8787, or warn when it is taken)
    cluster = LocalCluster(n_workers=workers or default_workers(), threads_per_worker=1, processes=True,
                           dashboard_address=":0", scheduler_kwargs={"dashboard": False}, silence_logs=logging.ERROR)
    client = Client(cluster, set_as_default=set_as_default)
    from footprint.local_workers import Niceness, ParentStops

    client.register_plugin(ParentStops())  # every worker, and each one that replaces a worker later
    if niceness:
        client.register_plugin(Niceness(niceness))

    def close():
        client.close()
        cluster.close()

    return client, close


@contextmanager
def dask_client(client=None, *, workers: int | None = None, scheduler: str | None = None):
    """The client to submit to: the one given, else start_client's, closed on exit."""
    if client is not None:
        yield client
        return
    started, close = start_client(workers=workers, scheduler=scheduler)
    try:
        yield started
    finally:
        close()


def client_map(client):
    """A callable with builtin map's signature that runs func on the client's workers, one task per item, and
    returns the results in order. func must be picklable (defined at module level); pure=False: each item is
    run, none taken for another's result by its arguments' hash."""
    def map_tasks(func, *iterables):
        return client.gather(client.map(func, *iterables, pure=False))

    return map_tasks


def worker_count(client) -> int:
    """How many workers the client's scheduler has now."""
    return len(client.scheduler_info(n_workers=-1)["workers"])

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


@contextmanager
def dask_client(client=None, *, workers: int | None = None, scheduler: str | None = None):
    """The client to submit to: the one given; or one connected to `scheduler` ("tcp://host:port"); or a
    LocalCluster of `workers` processes (default: the cores), one thread each, closed on exit."""
    from distributed import Client, LocalCluster

    if client is not None:
        yield client
        return
    if scheduler is not None:
        with Client(scheduler, timeout="10s") as c:
            yield c
        return
    # ":0": any free port for the scheduler's HTTP routes (None would still take 8787, or warn when it is taken)
    with LocalCluster(n_workers=workers or default_workers(), threads_per_worker=1, processes=True,
                      dashboard_address=":0", silence_logs=logging.ERROR) as cluster, Client(cluster) as c:
        yield c


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

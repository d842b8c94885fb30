"""How a local cluster's workers start. They are ready when start_client returns (parallel.Warm): every kind's
contract module imported and numba's integrator loaded, before any task of theirs; a worker that replaces one too.
Before, a fresh worker did it in its first task (a dispersion chunk: 2.1 s against 0.8 s for the next). And they keep
glibc's own malloc thresholds: Dask's nanny set MALLOC_TRIM_THRESHOLD_, which made every flight's rows new pages."""

import os

from footprint.parallel import start_client


def ready() -> bool:
    """Run in a worker (client.run: outside any task): the contract modules imported, the integrator compiled."""
    import sys

    from footprint import contracts

    integrate = sys.modules.get("footprint.core.integrate")
    kernel = getattr(integrate, "integrate", None)
    return all(name in sys.modules for name in contracts.MODULES.values()) and bool(getattr(kernel, "overloads", {}))


def test_every_worker_and_each_replacement_is_warm_before_its_first_task():
    client, close = start_client(workers=2, set_as_default=False)
    try:
        pids = client.run(os.getpid)
        assert len(pids) == 2
        assert set(client.run(ready).values()) == {True}
        client.restart(timeout=120)  # new worker processes under the same nannies
        client.wait_for_workers(2, timeout=120)
        assert set(client.run(os.getpid).values()).isdisjoint(pids.values())
        assert set(client.run(ready).values()) == {True}
    finally:
        close()


def trim_threshold() -> str | None:
    return os.environ.get("MALLOC_TRIM_THRESHOLD_")


def test_the_workers_keep_glibcs_malloc_thresholds(monkeypatch):
    # a nanny started here before (a test's own LocalCluster) leaves its setting in this process's environment
    monkeypatch.delenv("MALLOC_TRIM_THRESHOLD_", raising=False)
    client, close = start_client(workers=1, set_as_default=False)
    try:
        assert set(client.run(trim_threshold).values()) == {None}
    finally:
        close()

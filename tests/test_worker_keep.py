"""Issue 49 item 6: a local cluster keeps its workers on a busy machine (parallel.WorkerKeeper, kept_at_size).

On a long run beside other work the suite's cluster lost its workers one by one and never got them back. The cause,
found in distributed's logs: a worker restarted (a cancelled job's task, a crash) whose new process took longer than
distributed.deploy.lost-worker-timeout (15 s) to come back had its nanny closed by the cluster, mid-start (a cancel's
restart on the loaded machine took 20 s), and nothing started another. Here a worker's new process is made slow to
start on purpose (its preload sleeps 25 s) and the old one is killed."""

import os
import signal
import textwrap
import time

import pytest
from distributed import Client, LocalCluster

from footprint.parallel import kept_at_size

SLOW_START_S = 25.0  # past distributed's 15 s
WAIT_S = 180.0  # a guard against a hang on a loaded machine, never a bound on speed


@pytest.fixture
def slow_restart(tmp_path):
    """A preload whose worker sleeps SLOW_START_S before it registers, once the marker file exists."""
    marker = tmp_path / "slow"
    preload = tmp_path / "slow_start.py"
    preload.write_text(textwrap.dedent(f"""
        import os, time

        def dask_setup(worker):
            if os.path.exists({str(marker)!r}):
                time.sleep({SLOW_START_S})
    """))  # fmt: skip
    return str(preload), marker


def workers(client: Client) -> dict[str, int]:
    """{name: pid} of the workers the scheduler has."""
    return {str(w["name"]): a for a, w in client.scheduler_info(n_workers=-1)["workers"].items()}


def wait_for(condition, what: str):
    deadline = time.monotonic() + WAIT_S
    while not (value := condition()):
        assert time.monotonic() < deadline, f"{what}: not within {WAIT_S:g} s"
        time.sleep(0.2)
    return value


def test_a_worker_slow_to_come_back_is_waited_for_and_a_lost_one_replaced(slow_restart):
    preload, marker = slow_restart
    with (
        LocalCluster(
            n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0",
            scheduler_kwargs={"dashboard": False}, preload=[preload],
        ) as cluster,
        Client(cluster, set_as_default=False) as client,
        kept_at_size(cluster),
    ):  # fmt: skip
        (name,) = workers(client)
        pid = client.run(os.getpid)[workers(client)[name]]
        marker.touch()  # the next process of this worker starts slowly
        os.kill(pid, signal.SIGKILL)
        wait_for(lambda: not workers(client), "the scheduler sees the worker gone")
        back = wait_for(lambda: workers(client), "the worker comes back")
        assert list(back) == [name]
        assert client.run(os.getpid)[back[name]] != pid
        marker.unlink()
        # and one whose nanny is gone for good (a failed restart closes it): replaced under its name
        (nanny,) = cluster.workers.values()
        cluster.sync(nanny.close)
        wait_for(lambda: not workers(client), "the worker is gone")
        assert list(wait_for(lambda: workers(client), "a new worker")) == [name]

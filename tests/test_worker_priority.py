"""The local cluster's workers fly at a lower CPU priority than the process that starts them (issue 24 item 7: the
API process's readers waited behind two jobs' flights). Each thread's nice value is read by this process from
/proc, not by the plugin that set it; a worker started later to replace one gets it too."""

import os
from pathlib import Path

import pytest

from footprint.parallel import start_client

pytestmark = pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="reads the threads' nice from /proc")


def thread_nice(pid: int) -> dict[int, int]:
    """{thread id: nice} of a process, from /proc/PID/task/TID/stat (field 19, counted past the command's ")")."""
    out = {}
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            fields = (task / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:  # the thread ended meanwhile
            continue
        out[int(task.name)] = int(fields[16])
    return out


def flown_priority() -> int:
    """A task: the nice value of the thread that runs it."""
    return os.getpriority(os.PRIO_PROCESS, 0)


def test_every_worker_thread_and_each_replacement_flies_at_the_niceness():
    ours = os.getpriority(os.PRIO_PROCESS, 0)
    client, close = start_client(workers=2, niceness=10, set_as_default=False)
    try:
        pids = client.run(os.getpid)
        assert len(pids) == 2
        for pid in pids.values():
            assert set(thread_nice(pid).values()) == {max(10, ours)}, pid
        assert client.submit(flown_priority, pure=False).result(timeout=60) == max(10, ours)
        assert set(thread_nice(os.getpid()).values()) == {ours}  # the starting process (the API's) is untouched

        client.restart(timeout=120)  # new worker processes under the same nannies
        client.wait_for_workers(2, timeout=120)
        replaced = client.run(os.getpid)
        assert set(replaced.values()).isdisjoint(pids.values())
        for pid in replaced.values():
            assert set(thread_nice(pid).values()) == {max(10, ours)}, pid
    finally:
        close()


def test_without_a_niceness_the_workers_keep_their_parents():
    ours = os.getpriority(os.PRIO_PROCESS, 0)
    client, close = start_client(workers=1, set_as_default=False)
    try:
        for pid in client.run(os.getpid).values():
            assert set(thread_nice(pid).values()) == {ours}
    finally:
        close()

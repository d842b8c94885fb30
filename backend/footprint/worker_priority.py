"""The local cluster's workers at a lower CPU priority than the process that serves the API (nice(2)): a flight can
wait a few milliseconds, a reader of the map cannot (issue 24 item 7: 200 readers' p99 was 1.8 s while two jobs
held both cores)."""

import os

from distributed.diagnostics.plugin import WorkerPlugin


class Niceness(WorkerPlugin):
    """Every thread of the worker's process at `niceness` or nicer: on Linux setpriority(2) sets one thread's value
    and a new thread inherits its creator's, so the executor thread that flies the tasks (and any thread it starts)
    runs at it."""

    name = "footprint-niceness"
    idempotent = True

    def __init__(self, niceness: int):
        self.niceness = niceness

    def setup(self, worker) -> None:
        for tid in _threads():
            try:
                os.setpriority(os.PRIO_PROCESS, tid, max(self.niceness, os.getpriority(os.PRIO_PROCESS, tid)))
            except OSError:  # a thread gone meanwhile: the others still go
                pass


def _threads() -> list[int]:
    """This process's thread ids (0, the calling thread, where /proc does not list them)."""
    try:
        return [int(t) for t in os.listdir("/proc/self/task")]
    except OSError:
        return [0]

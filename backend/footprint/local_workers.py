"""The local cluster's worker processes, as worker plugins (each worker, and every one that replaces a worker later):

- at a lower CPU priority than the process that serves the API (nice(2)): a flight can wait a few milliseconds, a
  reader of the map cannot (issue 24 item 7: 200 readers' p99 was 1.8 s while two jobs held both cores);
- deaf to the terminal's Ctrl+C, which reaches the whole process group: the service closes its cluster itself, and
  each worker's own KeyboardInterrupt printed a 30-line traceback over the shutdown (issue 25 item 8).
"""

import os
import signal

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


class ParentStops(WorkerPlugin):
    """SIGINT ignored in the worker's process (its main thread runs the worker's event loop, where setup is called):
    the service that started the cluster stops it."""

    name = "footprint-parent-stops"
    idempotent = True

    def setup(self, worker) -> None:
        signal.signal(signal.SIGINT, signal.SIG_IGN)

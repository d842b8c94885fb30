"""What `footprint serve` says on its console (issue 25 items 6 and 8): each start-up step and how long the flight
kernels took (a first start compiled for a minute in silence), and nothing but uvicorn's own lines when Ctrl+C
stops it (the signal reaches the whole process group: each Dask worker printed a KeyboardInterrupt traceback)."""

import os
import signal
import time

from tests.service.conftest import wait_until
from tests.service.test_restart import free_port, kill, start


def test_a_start_says_what_it_does_and_ctrl_c_stops_it_quietly(tmp_path):
    proc = start(tmp_path, free_port())
    try:
        (log_path,) = tmp_path.glob("serve-*.log")
        wait_until(lambda: "flight kernels are ready" in log_path.read_text(), "the workers warmed")
        text = log_path.read_text()
        for step in (
            "footprint: migrating the database",
            "footprint: starting the job engine (a local cluster of 2",
            "footprint: loading the flight kernels (numba): a first start compiles them",
            "footprint: ready (the flight kernels took",
            "footprint: the workers' flight kernels are ready (",
        ):
            assert step in text, text
        os.killpg(proc.pid, signal.SIGINT)  # what Ctrl+C in a terminal does
        wait_until(lambda: proc.poll() is not None, "serve stopped by SIGINT")
        time.sleep(1.0)  # a worker's last words, if any, after the parent
        said = log_path.read_text()[len(text) :]
        assert proc.returncode in (0, 128 + signal.SIGINT, -signal.SIGINT), said  # uvicorn re-raises the signal
        assert "Traceback" not in said and "ERROR" not in said and "CommClosedError" not in said, said
        assert "Application shutdown complete" in said
    finally:
        if proc.poll() is None:
            kill(proc)

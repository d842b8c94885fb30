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


def test_health_says_starting_from_the_first_second_and_each_step_is_timed(tmp_path):
    """Issue 53 item 11: `serve` printed its URL at once and answered ~3.5 min later, silent for ~3 min and without
    times. Its socket opens at once now: health answers 503 "starting" with the step under way, any other API
    request 503 saying so, until it is ready and health says ok; every console line begins with its UTC time."""
    import re

    import httpx

    from tests.service.test_restart import START_TIMEOUT_S, launch

    port = free_port()
    proc, log_path = launch(tmp_path, port, workers=1)
    try:
        answers, refused = [], None
        deadline = time.monotonic() + START_TIMEOUT_S
        while time.monotonic() < deadline and (not answers or answers[-1][1] != "ok"):
            assert proc.poll() is None, log_path.read_text()
            try:
                r = httpx.get(f"http://127.0.0.1:{port}/api/health", timeout=5)
                answers.append((r.status_code, r.json()["status"], r.json().get("starting")))
                if r.json()["status"] == "starting" and refused is None:
                    refused = httpx.get(f"http://127.0.0.1:{port}/api/vehicles", timeout=5)
            except httpx.TransportError:
                pass
            time.sleep(0.05)
        assert answers and answers[-1][:2] == (200, "ok"), answers[-5:]
        first = answers[0]
        assert first[:2] == (503, "starting") and first[2], answers[:3]  # the step under way, from the first answer
        assert {a[2] for a in answers if a[1] == "starting"} <= {
            "starting",
            "migrating the database",
            "starting the job engine (a local cluster of 1 workers)",
            "loading the flight kernels (numba): a first start compiles them, about a minute; later ones load them "
            "from its cache in seconds",
        }, answers
        assert refused is not None and refused.status_code == 503 and "starting" in refused.json()["detail"]
        text = log_path.read_text()
        for step in ("migrating the database", "starting the job engine", "ready (the flight kernels took"):
            assert re.search(rf"^\d\d:\d\d:\d\dZ footprint: {re.escape(step)}", text, re.M), text
        assert httpx.get(f"http://127.0.0.1:{port}/api/vehicles", timeout=30).status_code == 200
    finally:
        if proc.poll() is None:
            kill(proc)

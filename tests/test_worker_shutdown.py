"""A closing worker's heartbeat, cut off by its own close, is not an error on the console (CI of stop 37:
Ctrl+C on `footprint serve` printed distributed's "Failed to communicate with scheduler during heartbeat" and a
40-line CommClosedError traceback on a loaded machine); while the worker runs, the same failure is still reported."""

import logging
from types import SimpleNamespace

import pytest
from distributed.core import Status

from footprint.parallel import ClosingHeartbeat

HEARTBEAT_FAILED = "Failed to communicate with scheduler during heartbeat."  # distributed.worker.Worker.heartbeat


@pytest.mark.parametrize(
    ("status", "reported"),
    [(Status.running, True), (Status.paused, True), (Status.closing, False), (Status.closed, False)],
)
def test_a_heartbeat_failure_is_reported_only_while_the_worker_runs(caplog, status, reported):
    worker = SimpleNamespace(status=status)
    logger = logging.getLogger("distributed.worker")
    heartbeat = ClosingHeartbeat(worker)
    logger.addFilter(heartbeat)
    try:
        with caplog.at_level(logging.ERROR, logger="distributed.worker"):
            try:
                raise OSError("Stream is closed")
            except OSError:
                logger.exception(HEARTBEAT_FAILED)  # as distributed logs it
            logger.error("Something else failed")
    finally:
        logger.removeFilter(heartbeat)
    said = [r.getMessage() for r in caplog.records]
    assert (HEARTBEAT_FAILED in said) is reported
    assert "Something else failed" in said

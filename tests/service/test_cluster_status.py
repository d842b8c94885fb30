"""/api/health's view of the cluster (jobs.engine.ClusterLink.recent_status): answered at once from the scheduler's
last answer while one thread asks again (issue 24 item 7: asked in the request's turn, the round trip to a busy
scheduler held the readers that came at that moment past a second). A scheduler that does not answer is asked by
one thread, not one per reader, and its next answer is what health then shows."""

import threading
import time

from footprint.service.jobs import engine
from footprint.service.settings import Settings

from .conftest import wait_until


class Scheduler:
    """A Dask client whose scheduler answers only when released."""

    status = "running"

    def __init__(self, workers: int):
        self.workers, self.asked, self.release = workers, 0, threading.Event()

    def scheduler_info(self, n_workers: int) -> dict:
        self.asked += 1
        assert self.release.wait(60), "never released"
        return {"address": "tcp://10.0.0.1:8786", "workers": {f"w{i}": {} for i in range(self.workers)}}


def test_health_reads_the_last_answer_while_one_thread_asks_again(monkeypatch, tmp_path):
    monkeypatch.setattr(engine, "STATUS_S", 0.05)
    link = engine.ClusterLink(settings=Settings(database_url=f"sqlite:///{tmp_path / 'x.db'}", dask_workers=2))
    link.client = scheduler = Scheduler(workers=2)
    assert link.recent_status() is None  # nothing asked yet: the route asks in the thread pool
    scheduler.release.set()
    assert link.status()["workers"] == 2 and link.status()["ok"]

    scheduler.release.clear()
    scheduler.workers = 1  # a worker lost: the scheduler will say so once it answers
    time.sleep(0.1)  # the answer is older than STATUS_S
    last = link.recent_status()  # returns although the scheduler does not answer
    assert last == {"ok": True, "scheduler": "tcp://10.0.0.1:8786", "workers": 2, "expected_workers": 2}
    wait_until(lambda: scheduler.asked == 2, "a thread asks the scheduler")  # one thread asks
    for _ in range(20):
        assert link.recent_status()["workers"] == 2
    assert scheduler.asked == 2  # and only that one

    scheduler.release.set()
    wait_until(lambda: link.recent_status()["workers"] == 1, "health shows the answer")
    assert link.recent_status()["ok"] is False and link.recent_status()["expected_workers"] == 2

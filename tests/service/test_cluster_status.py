"""/api/health's view of the cluster and the link that keeps it (jobs.engine.ClusterLink): one watching thread asks
the scheduler every WATCH_S; health reads its last look at once (issue 24 item 7: a reader never waits on a busy
scheduler), and says "degraded" the moment the client is not connected or once the scheduler has not answered for
STALE_S (issue 49 item 1: health said "ok" for ~10 s with no scheduler). Every new connection renews the client's
event subscriptions (a restarted scheduler knew none of them: the jobs' progress never came again) and moves the
link's generation on (the tasks submitted before it are lost). A fake client stands in for Dask's here; the real
processes are killed and restarted in test_scheduler_restart."""

import threading

from footprint.service.jobs import engine
from footprint.service.settings import Settings

from .conftest import wait_until


class Client:
    """Dask's client as the link uses it: status, the scheduler's identity (asked through sync, answered when
    released), its connection and subscriptions."""

    def __init__(self, workers: int):
        self.status, self.workers, self.asked = "running", workers, 0
        self.release = threading.Event()
        self.release.set()
        self.scheduler_comm, self.scheduler_id, self.subscribed = object(), "Scheduler-1", []
        self.scheduler = self  # client.scheduler.identity

    def identity(self, n_workers: int) -> dict:
        return {"id": self.scheduler_id, "address": "tcp://10.0.0.1:8786",
                "workers": {f"tcp://10.0.0.1:{9000 + i}": {"name": f"w{i}"} for i in range(self.workers)}}  # fmt: skip

    def sync(self, func, *args, callback_timeout: float, **kwargs):
        self.asked += 1
        if not self.release.wait(callback_timeout):
            raise TimeoutError(f"timed out after {callback_timeout} s")
        return func(*args, **kwargs)

    def subscribe_topic(self, topic: str, handler) -> None:
        self.subscribed.append(topic)


def link_of(monkeypatch, tmp_path, client: Client, **settings) -> engine.ClusterLink:
    monkeypatch.setattr(engine, "WATCH_S", 0.02)
    monkeypatch.setattr(engine, "ASK_TIMEOUT_S", 0.2)
    monkeypatch.setattr(engine, "STALE_S", 0.5)
    values = {"database_url": f"sqlite:///{tmp_path / 'x.db'}", "dask_workers": 2} | settings
    link = engine.ClusterLink(settings=Settings(**values))
    monkeypatch.setattr(link, "_connect", lambda: (client, lambda: None))
    link.start_link()
    return link


def test_health_reads_the_watchs_last_look_without_asking_the_scheduler(monkeypatch, tmp_path):
    client = Client(workers=2)
    link = link_of(monkeypatch, tmp_path, client)
    try:
        assert link.recent_status() == {"ok": True, "scheduler": "tcp://10.0.0.1:8786", "workers": 2,
                                        "expected_workers": 2}  # fmt: skip
        client.workers, asked = 1, client.asked  # a worker lost: the next look says so, whether anyone asks or not
        wait_until(lambda: client.asked >= asked + 2, "the watch looks again")
        status = link.recent_status()  # the first answer after a quiet spell is fresh (with several API
        # processes, the one asked after a while answered from its old view first: health flapped between views)
        assert not status["ok"] and status["error"] == "1 of 2 workers"
        asked = client.asked
        for _ in range(50):
            link.recent_status()
        assert client.asked - asked < 50  # readers do not ask: only the watch does
    finally:
        link.close()


def test_a_scheduler_that_stops_answering_is_degraded_after_stale_s_and_ok_again_when_it_answers(monkeypatch, tmp_path):
    client = Client(workers=2)
    link = link_of(monkeypatch, tmp_path, client, dask_scheduler="tcp://10.0.0.1:8786")
    try:
        assert link.recent_status()["ok"]
        client.release.clear()  # a hung scheduler: the client stays "running", no answer comes
        status = wait_until(lambda: (s := link.recent_status())["ok"] is False and s, "degraded")
        assert status["error"].startswith("no answer from the Dask scheduler (<address>) for ")
        assert "10.0.0.1" not in str(status["error"])  # the address is the operator's
        assert link.unrunnable_s() > 0
        client.release.set()
        wait_until(lambda: link.recent_status()["ok"], "ok again")
        assert link.unrunnable_s() == 0.0
    finally:
        client.release.set()
        link.close()


def test_a_client_that_lost_its_scheduler_is_degraded_at_once(monkeypatch, tmp_path):
    client = Client(workers=2)
    link = link_of(monkeypatch, tmp_path, client)
    try:
        client.status = "connecting"  # Dask's client saw its connection close: no look needed to say so
        status = link.recent_status()
        assert status["ok"] is False and status["error"].startswith("no answer from the Dask scheduler (local)")
    finally:
        link.close()


def test_every_new_connection_renews_the_subscriptions_and_moves_the_generation_on(monkeypatch, tmp_path):
    client = Client(workers=2)
    link = link_of(monkeypatch, tmp_path, client)
    try:
        topics = sorted(link._topics)
        assert sorted(client.subscribed) == topics and link.generation == 1
        client.scheduler_comm = object()  # Dask's client reconnected (a new scheduler, or the same one)
        wait_until(lambda: link.generation == 2, "renewed on the reconnection")
        client.scheduler_id = "Scheduler-2"  # a restarted scheduler at the same address
        wait_until(lambda: link.generation == 3, "renewed on the new scheduler")
        assert sorted(client.subscribed) == sorted(topics * 3)
    finally:
        link.close()


def test_a_client_that_gave_up_is_built_again(monkeypatch, tmp_path):
    first, second = Client(workers=2), Client(workers=2)
    link = link_of(monkeypatch, tmp_path, first)
    try:
        monkeypatch.setattr(link, "_connect", lambda: (second, lambda: None))
        first.status = "closed"  # Dask's client closes itself after 10 s without its scheduler
        wait_until(lambda: link.client is second and link.recent_status()["ok"], "a new client")
        assert sorted(second.subscribed) == sorted(link._topics) and link.generation == 2
    finally:
        link.close()

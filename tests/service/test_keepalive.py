"""A 500 keeps the client's keep-alive connection (issue 15 item 7): Starlette's ServerErrorMiddleware sends the 500
and raises again, and uvicorn closes the connection of a request whose app raised after its response started, so
the client's next request on it failed with a reset. Against a real uvicorn server, one httpx connection."""

import socket
import threading

import httpx
import pytest

from .conftest import wait_until


@pytest.fixture(scope="module")
def server(scheduler_address, tmp_path_factory):
    import uvicorn

    from footprint.service.app import create_app
    from footprint.service.settings import load_settings

    url = f"sqlite:///{tmp_path_factory.mktemp('keepalive') / 'footprint.db'}"
    app = create_app(load_settings(database_url=url, dask_scheduler=scheduler_address))
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", timeout_keep_alive=30))
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    # the lifespan: migrations, the cluster's numba warm-up
    wait_until(lambda: server.started or not thread.is_alive(), "uvicorn starts")
    assert server.started, "uvicorn exited while starting"
    yield f"http://127.0.0.1:{sock.getsockname()[1]}"
    server.should_exit = True
    thread.join(30)


def local_address(response: httpx.Response):
    return response.extensions["network_stream"].get_extra_info("client_addr")


def test_a_500_keeps_the_connection(server, monkeypatch):
    from footprint.service.db import queries

    def broken(*_args, **_kwargs):
        raise RuntimeError("a bug in a query")

    monkeypatch.setattr(queries, "list_sites", broken)
    with httpx.Client(base_url=server, limits=httpx.Limits(max_connections=1), timeout=30) as client:
        connection = local_address(client.get("/api/health"))
        for _ in range(3):
            failed = client.get("/api/sites")
            assert failed.status_code == 500
            assert failed.json() == {"detail": "internal error (the server's log has the traceback)"}
            after = client.get("/api/health")  # a reset here, or a new connection, before the fix
            assert after.status_code == 200 and local_address(after) == connection

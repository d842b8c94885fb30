"""Settings from FOOTPRINT_* variables with the documented defaults, checked at start-up; the map page's static
files served at / next to the API."""

import pytest
from pydantic import ValidationError

from footprint.parallel import default_workers
from footprint.service.settings import load_settings

from .conftest import database_url, running_service


@pytest.fixture
def clean_env(monkeypatch):
    for name in (
        "DATABASE_URL",
        "DASK_SCHEDULER",
        "DASK_WORKERS",
        "API_TOKEN",
        "CORS_ORIGINS",
        "TILE_URL",
        "HOST",
        "PORT",
        "HEADER_TIMEOUT_S",
        "BODY_TIMEOUT_S",
        "ACCESS_LOG",
    ):
        monkeypatch.delenv(f"FOOTPRINT_{name}", raising=False)
    return monkeypatch


def test_the_defaults_are_sqlite_in_the_working_directory_a_local_cluster_and_loopback(clean_env):
    clean_env.delenv("FOOTPRINT_ALLOWED_HOSTS", raising=False)  # the tests' "testserver" (tests/conftest.py)
    s = load_settings()
    assert (s.database_url, s.dask_scheduler, s.api_token, s.host, s.port) == (
        "sqlite:///footprint.db",
        "",
        "",
        "127.0.0.1",
        8000,
    )
    assert s.dask_workers == default_workers() and s.cors_origin_list == []
    assert s.host_names == {"localhost", "127.0.0.1", "[::1]"}
    assert (s.header_timeout_s, s.body_timeout_s) == (10.0, 30.0)


def test_uvicorn_logs_each_request_only_when_asked(clean_env):
    """Issue 49: the access log's line per request was 7 % of the event loop's samples at 200 readers."""
    from footprint.service import server

    assert server.config(load_settings(), app=None).access_log is False
    clean_env.setenv("FOOTPRINT_ACCESS_LOG", "1")
    assert server.config(load_settings(), app=None).access_log is True


@pytest.mark.parametrize(
    "host, allowed, names",
    [
        ("0.0.0.0", "", set()),
        ("::", "", set()),  # a wildcard bind names no host: FOOTPRINT_ALLOWED_HOSTS does
        ("192.168.1.20", "", {"192.168.1.20"}),
        ("fd00::5", "", {"[fd00::5]"}),
        ("0.0.0.0", " Footprint.Example , planner.lan", {"footprint.example", "planner.lan"}),
        ("0.0.0.0", "*", {"*"}),
    ],
)
def test_the_served_host_names(clean_env, host, allowed, names):
    assert load_settings(host=host, allowed_hosts=allowed).host_names == {"localhost", "127.0.0.1", "[::1]"} | names


def test_the_environment_and_overrides_are_read_and_checked(clean_env):
    clean_env.setenv("FOOTPRINT_DASK_SCHEDULER", "tcp://scheduler:8786")
    clean_env.setenv("FOOTPRINT_CORS_ORIGINS", "https://a.example, https://b.example")
    clean_env.setenv("FOOTPRINT_PORT", "9000")
    s = load_settings(port=None, host="0.0.0.0")
    assert (s.dask_scheduler, s.port, s.host) == ("tcp://scheduler:8786", 9000, "0.0.0.0")
    assert s.cors_origin_list == ["https://a.example", "https://b.example"]
    clean_env.setenv("FOOTPRINT_DASK_SCHEDULER", "scheduler:8786")
    with pytest.raises(ValidationError, match="tcp://host:8786"):
        load_settings()
    with pytest.raises(ValidationError, match="dask_workers"):
        load_settings(dask_workers=0, dask_scheduler="")


def test_the_settings_pass_to_another_process_through_the_environment(clean_env):
    """`serve --api-processes N` hands its settings (the CLI's overrides included) to uvicorn's processes this way."""
    from footprint.service.settings import Settings, environment

    given = load_settings(
        database_url="postgresql+psycopg://db/x",
        port=9001,
        api_token="t",
        api_processes=3,
        cors_origins="https://a.example",
        job_time_limit_s=12.5,
        dask_workers=5,
    )
    for name, value in environment(given).items():
        clean_env.setenv(name, value)
    assert load_settings() == given and set(environment(given)) == {
        f"FOOTPRINT_{n.upper()}" for n in Settings.model_fields
    }


def test_the_page_is_served_at_the_root(scheduler_address, tmp_path):
    page = tmp_path / "page"
    page.mkdir()
    (page / "index.html").write_text("<!doctype html><title>Footprint map</title>")
    with database_url("sqlite", tmp_path) as url, running_service(url, scheduler_address, frontend_dir=page) as api:
        assert "Footprint map" in api.get("/").text
        assert api.get("/api/health").json()["status"] == "ok" and api.get("/docs").status_code == 200


@pytest.mark.parametrize("tile_url", ["", "https://tiles.example/{z}/{x}/{y}.png"])
def test_the_page_config_carries_the_tile_url(clean_env, scheduler_address, tmp_path, tile_url):
    import footprint

    with database_url("sqlite", tmp_path) as url, running_service(url, scheduler_address, tile_url=tile_url) as api:
        assert api.get("/api/config").json() == {"tile_url": tile_url or None, "version": footprint.__version__}
        assert "/api/config" in api.get("/openapi.json").json()["paths"]

"""docker-compose.yml: valid against the official Compose Specification schema (tests/authorities/,
see compose-spec.SOURCE.md there) and consistent with the code: the settings it sets, the routes and
ports its health checks use, the dask command lines it runs (started here for real, on loopback)."""

import copy
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import time
import urllib.parse
import urllib.request

import jsonschema
import pytest
import yaml
from deploy_files import (
    COMPOSE,
    COMPOSE_SCHEMA,
    DOCKERFILE,
    ROOT,
    assert_real_settings,
    get_routes,
    health_url,
    parse_dockerfile,
    stages,
)

# Go durations, as the schema's "duration" format means them (1m30s, 5s, 250ms)
_DURATION = re.compile(r"^(\d+(\.\d+)?(ns|us|µs|ms|s|m|h))+$")


@pytest.fixture(scope="module")
def compose():
    return yaml.safe_load(COMPOSE.read_text())


@pytest.fixture(scope="module")
def validator():
    schema = json.loads(COMPOSE_SCHEMA.read_text())
    assert schema["title"] == "Compose Specification"
    checker = jsonschema.FormatChecker()
    checker.checks("duration")(lambda v: not isinstance(v, str) or bool(_DURATION.match(v)))
    jsonschema.Draft201909Validator.check_schema(schema)
    return jsonschema.Draft201909Validator(schema, format_checker=checker)


def services_running(compose, *words):
    return {name: s for name, s in compose["services"].items() if _command(s)[: len(words)] == list(words)}


def _command(service):
    cmd = service.get("command", [])
    return cmd if isinstance(cmd, list) else cmd.split()


def _env(service):
    env = service.get("environment", {})
    if isinstance(env, list):
        env = dict(item.split("=", 1) for item in env)
    return {k: str(v) for k, v in env.items()}


def _option(words, name):
    i = words.index(name)
    return words[i + 1]


def _image_service(compose, image):
    (name,) = [n for n, s in compose["services"].items() if s.get("image", "").split(":")[0] == image]
    return name, compose["services"][name]


def _api(compose):
    (name,) = services_running(compose, "footprint", "serve")
    return name, compose["services"][name]


# ---- the schema


def test_valid_against_the_compose_specification(compose, validator):
    errors = sorted(validator.iter_errors(compose), key=lambda e: list(e.path))
    assert not errors, "\n".join(f"{'/'.join(map(str, e.path))}: {e.message}" for e in errors)


@pytest.mark.parametrize(
    "breakage",
    [
        lambda c: c["services"]["api"].update(helthcheck={"test": ["CMD", "true"]}),
        lambda c: c["services"]["postgres"]["healthcheck"].update(interval="5 seconds"),
        lambda c: c["services"]["api"]["depends_on"]["postgres"].update(condition="service_ready"),
        lambda c: c.update(service={}),
    ],
    ids=["misspelled-key", "bad-duration", "bad-condition", "unknown-top-level"],
)
def test_the_schema_catches_mistakes(compose, validator, breakage):
    broken = copy.deepcopy(compose)
    breakage(broken)
    assert list(validator.iter_errors(broken))


def test_docker_compose_config_if_available():
    docker = shutil.which("docker")
    if not docker or subprocess.run([docker, "compose", "version"], capture_output=True).returncode != 0:
        pytest.skip("no docker compose plugin on this machine")
    run = subprocess.run([docker, "compose", "-f", str(COMPOSE), "config", "--quiet"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


# ---- the services


def test_every_service_has_a_health_check_and_depends_only_on_healthy_services(compose):
    services = compose["services"]
    for name, s in services.items():
        hc = s.get("healthcheck")
        assert hc and hc.get("test") and not hc.get("disable"), f"{name}: no health check"
        deps = s.get("depends_on", {})
        assert isinstance(deps, dict), f"{name}: depends_on with conditions"
        for dep, cond in deps.items():
            assert dep in services, f"{name} depends on unknown {dep}"
            assert cond["condition"] == "service_healthy", f"{name} -> {dep}"


def test_postgres_has_a_named_volume_and_pg_isready(compose):
    name, pg = _image_service(compose, "postgres")
    assert ":" in pg["image"] and not pg["image"].endswith(":latest"), "pin the postgres version"
    volumes = [v.split(":") for v in pg["volumes"]]
    data = [v for v in volumes if v[1] == "/var/lib/postgresql/data"]
    assert data, "the database lives on a volume"
    assert data[0][0] in (compose.get("volumes") or {}), "a named volume declared at the top level"
    env = _env(pg)
    test = pg["healthcheck"]["test"]
    assert test[0] in ("CMD", "CMD-SHELL") and "pg_isready" in " ".join(test)
    assert env["POSTGRES_USER"] in " ".join(test) and env["POSTGRES_DB"] in " ".join(test)


def test_api_database_url_points_at_the_postgres_service(compose):
    from sqlalchemy.engine import make_url

    pg_name, pg = _image_service(compose, "postgres")
    _, api = _api(compose)
    url = make_url(_env(api)["FOOTPRINT_DATABASE_URL"])
    pg_env = _env(pg)
    assert url.drivername == "postgresql+psycopg"
    assert (url.host, url.port or 5432) == (pg_name, 5432)
    assert (url.username, url.password, url.database) == (
        pg_env["POSTGRES_USER"],
        pg_env["POSTGRES_PASSWORD"],
        pg_env["POSTGRES_DB"],
    )
    assert api["depends_on"][pg_name]["condition"] == "service_healthy"
    # the driver the URL names is a dependency of the package the image installs
    import tomllib

    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    assert any(re.match(r"psycopg(\[|>|=|$)", d) for d in deps), "psycopg must be installed in the image"
    __import__("psycopg")


def test_api_uses_the_scheduler_service(compose):
    _, api = _api(compose)
    url = urllib.parse.urlsplit(_env(api)["FOOTPRINT_DASK_SCHEDULER"])
    assert url.scheme == "tcp"
    sched = services_running(compose, "dask", "scheduler")
    assert url.hostname in sched, "the scheduler address names the scheduler service"
    assert str(url.port) == _option(_command(sched[url.hostname]), "--port")
    assert api["depends_on"][url.hostname]["condition"] == "service_healthy"


def test_two_workers_from_the_image_that_holds_footprint(compose):
    _, api = _api(compose)
    (sched_name,) = services_running(compose, "dask", "scheduler")
    workers = services_running(compose, "dask", "worker")
    assert len(workers) == 2
    names = set()
    for name, w in workers.items():
        cmd = _command(w)
        assert cmd[2] == f"tcp://{sched_name}:{_option(_command(compose['services'][sched_name]), '--port')}"
        names.add(_option(cmd, "--name"))
        # the same build as the api: the image whose venv holds footprint (the tasks' code)
        assert w.get("build") == api.get("build") and w.get("image") == api.get("image"), name
        assert w["depends_on"][sched_name]["condition"] == "service_healthy"
    assert len(names) == 2, "distinct worker names"
    # the same command but for the name: test_dask_services_start... runs one of them for real
    (a, b) = [[w for w in _command(s) if w not in names] for s in workers.values()]
    assert a == b, "the workers differ by more than their names"
    sched = compose["services"][sched_name]
    assert sched.get("build") == api.get("build") and sched.get("image") == api.get("image")


def test_builds_and_images_exist(compose):
    for name, s in compose["services"].items():
        if "build" in s:
            build = s["build"] if isinstance(s["build"], dict) else {"context": s["build"]}
            context = (COMPOSE.parent / build.get("context", ".")).resolve()
            dockerfile = context / build.get("dockerfile", "Dockerfile")
            assert dockerfile.is_file(), f"{name}: {dockerfile} missing"
            assert dockerfile == DOCKERFILE
            if "target" in build:
                assert build["target"] in {s.name for s in stages(parse_dockerfile(dockerfile.read_text()))}
        else:
            image = s.get("image", "")
            assert re.fullmatch(r"[a-z0-9./_-]+:[A-Za-z0-9._-]+", image), f"{name}: pin a tag, got {image!r}"


def test_api_command_is_a_real_cli_command(compose):
    _, api = _api(compose)
    run = subprocess.run(_command(api) + ["--help"], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr


def test_compose_env_sets_only_real_settings(compose, monkeypatch):
    from footprint.service.settings import Settings

    for s in compose["services"].values():
        env = {k: v for k, v in _env(s).items() if k.startswith("FOOTPRINT_")}
        if env:
            with monkeypatch.context() as m:
                assert_real_settings(Settings, env, m)


def test_api_port_and_health_route(compose, tmp_path):
    from footprint.service.settings import Settings

    _, api = _api(compose)
    image_env = stages(parse_dockerfile(DOCKERFILE.read_text()))[-1].env()
    port = int(_env(api).get("FOOTPRINT_PORT", image_env.get("FOOTPRINT_PORT", Settings.model_fields["port"].default)))
    targets = [int(str(p).split(":")[-1].split("/")[0]) for p in api["ports"]]
    assert targets == [port], "the published port is the one the service listens on"
    url = urllib.parse.urlsplit(health_url(api["healthcheck"]["test"]))
    assert url.port == port and url.hostname in ("127.0.0.1", "localhost")
    assert url.path in get_routes(tmp_path)
    assert "--host" in _command(api) and _option(_command(api), "--host") == "0.0.0.0"


# ---- the dask command lines, run for real on loopback


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_ok(url, proc, seconds=30):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        assert proc.poll() is None, f"exited with {proc.returncode}"
        try:
            with urllib.request.urlopen(url, timeout=2) as r:
                return r.status, r.read().decode()
        except OSError:
            time.sleep(0.3)
    raise AssertionError(f"{url} did not answer in {seconds} s")


def _localize(cmd, replacements):
    """The compose command with its addresses moved to free loopback ports."""
    out = []
    for w in cmd:
        for old, new in replacements.items():
            w = w.replace(old, new)
        out.append(w)
    return out


def _health_port(service):
    return urllib.parse.urlsplit(health_url(service["healthcheck"]["test"])).port


def test_dask_services_start_and_answer_their_health_checks(compose, tmp_path):
    """Run the compose file's scheduler and worker commands (ports moved to free loopback ones): every
    option must be one dask accepts, the health URLs must answer, and the worker must import footprint."""
    ((sched_name, sched),) = services_running(compose, "dask", "scheduler").items()
    worker_name, worker = next(iter(services_running(compose, "dask", "worker").items()))
    s_cmd, w_cmd = _command(sched), _command(worker)
    port, s_http, w_http = _free_port(), _free_port(), _free_port()
    assert _health_port(sched) == int(_option(s_cmd, "--dashboard-address").rsplit(":", 1)[1])
    assert _health_port(worker) == int(_option(w_cmd, "--dashboard-address").rsplit(":", 1)[1])
    s_cmd = _localize(
        s_cmd,
        {
            "0.0.0.0": "127.0.0.1",
            _option(s_cmd, "--port"): str(port),
            _option(s_cmd, "--dashboard-address"): f"127.0.0.1:{s_http}",
        },
    )
    w_cmd = _localize(
        w_cmd,
        {
            f"tcp://{sched_name}:": "tcp://127.0.0.1:",
            w_cmd[2].rsplit(":", 1)[1]: str(port),
            _option(w_cmd, "--dashboard-address"): f"127.0.0.1:{w_http}",
        },
    ) + ["--host", "127.0.0.1"]
    assert s_cmd[0] == w_cmd[0] == "dask"
    s_cmd, w_cmd = ([sys.executable, "-m", "dask", *c[1:]] for c in (s_cmd, w_cmd))  # this interpreter's dask
    env = dict(os.environ)
    log_s, log_w = open(tmp_path / "scheduler.log", "w"), open(tmp_path / "worker.log", "w")
    scheduler = subprocess.Popen(s_cmd, stdout=log_s, stderr=subprocess.STDOUT, env=env, cwd=tmp_path)
    worker_p = None
    try:
        assert _wait_ok(f"http://127.0.0.1:{s_http}/health", scheduler) == (200, "ok")
        worker_p = subprocess.Popen(w_cmd, stdout=log_w, stderr=subprocess.STDOUT, env=env, cwd=tmp_path)
        assert _wait_ok(f"http://127.0.0.1:{w_http}/health", worker_p, 60) == (200, "ok")
        from distributed import Client

        with Client(f"tcp://127.0.0.1:{port}", timeout=20) as client:
            client.wait_for_workers(1, timeout=30)
            (info,) = client.scheduler_info()["workers"].values()
            assert info["name"].startswith(_option(_command(worker), "--name"))
            where = client.run(lambda: __import__("footprint").__file__)
            assert set(where.values()) == {__import__("footprint").__file__}, "the workers import this footprint"
    finally:
        for p in (worker_p, scheduler):
            if p is not None and p.poll() is None:
                p.terminate()
        for p in (worker_p, scheduler):
            if p is not None:
                try:
                    p.wait(timeout=20)
                except subprocess.TimeoutExpired:
                    p.kill()
        log_s.close()
        log_w.close()
    assert "Import preload module: footprint" in (tmp_path / "worker.log").read_text(), "workers --preload footprint"

"""Issue 15 item 1: every response of the service carries a Content-Security-Policy that allows no inline script
(but the hashed ones of /docs and of the folium map), X-Content-Type-Options and Referrer-Policy."""

import re

import pytest
from fastapi.testclient import TestClient

from footprint.csp import inline_script_hashes, tile_source

from .conftest import running_service
from .sample_requests import UNKNOWN_ID


def directives(policy: str) -> dict[str, list[str]]:
    return {d.split()[0]: d.split()[1:] for d in (p.strip() for p in policy.split(";")) if d}


def assert_secured(response, *, script_hashes=()):
    assert response.headers["x-content-type-options"] == "nosniff"
    assert response.headers["referrer-policy"] == "no-referrer"
    policy = directives(response.headers["content-security-policy"])
    assert policy["object-src"] == ["'none'"] and policy["base-uri"] == ["'none'"]
    assert policy["frame-ancestors"] == ["'none'"]
    assert "'unsafe-inline'" not in policy["script-src"] and "'unsafe-eval'" not in policy["script-src"]
    assert sorted(s for s in policy["script-src"] if s.startswith("'sha256-")) == sorted(script_hashes)
    return policy


@pytest.fixture(scope="module")
def client(scheduler_address, tmp_path_factory):
    url = f"sqlite:///{tmp_path_factory.mktemp('headers') / 'footprint.db'}"
    with running_service(url, scheduler_address) as c:
        yield c


@pytest.mark.parametrize(
    "path, status",
    [
        ("/api/health", 200),
        ("/api/footprints", 200),
        ("/api/vehicles", 200),
        ("/", 200),
        ("/js/main.js", 200),
        ("/styles.css", 200),
        ("/openapi.json", 200),
        ("/redoc", 200),
        ("/api/nope", 404),
        (f"/api/footprints/{UNKNOWN_ID}", 404),
        ("/api/footprints/0f0e", 422),
        ("/no-such-file.js", 404),
        ("/api/footprints?limit=nope", 422),
    ],
)
def test_every_get_carries_the_headers(client, path, status):
    r = client.get(path)
    assert r.status_code == status, r.text
    policy = assert_secured(r)
    assert policy["script-src"] == ["'self'"]


def test_writes_and_their_errors_carry_the_headers(client):
    bad = client.post("/api/trajectories", json={"vehicle": {"builtin": "nope"}})
    assert bad.status_code == 422
    assert_secured(bad)
    assert_secured(client.delete("/api/health"))  # 405 from the guard, before any route
    assert_secured(client.post("/api/jobs", content=b"x" * 20_000_000))  # 413 from the guard


def test_the_docs_allow_only_their_own_inline_set_up(client):
    r = client.get("/docs")
    hashes = inline_script_hashes(r.text)
    assert r.status_code == 200 and len(hashes) == 1 and "SwaggerUIBundle" in r.text
    assert_secured(r, script_hashes=hashes)


def test_the_tile_layer_origin_is_allowed_for_images(tmp_path):
    """FOOTPRINT_TILE_URL's origin (a Leaflet {s} subdomain as CSP's leftmost wildcard) joins img-src, nothing else."""
    from footprint.service.app import create_app
    from footprint.service.settings import load_settings

    settings = load_settings(
        database_url=f"sqlite:///{tmp_path / 'f.db'}", tile_url="https://{s}.tiles.example.org:8443/{z}/{x}/{y}.png"
    )
    r = TestClient(create_app(settings)).get("/api/config")  # no lifespan: the config needs no database
    policy = assert_secured(r)
    assert "https://*.tiles.example.org:8443" in policy["img-src"]
    assert "https://*.tiles.example.org:8443" not in policy["connect-src"] + policy["script-src"]


@pytest.mark.parametrize(
    "url, source",
    [
        ("", None),
        ("http://127.0.0.1:9000/tiles/{z}/{x}/{y}.png", "http://127.0.0.1:9000"),
        ("https://{s}.tile.openstreetmap.org/{z}/{x}/{y}.png", "https://*.tile.openstreetmap.org"),
        ("https://tiles.{s}.example.org/{z}/{x}/{y}.png", "https:"),
    ],
)
def test_tile_source(url, source):
    assert tile_source(url) == source


def test_no_page_file_has_an_inline_script_or_handler():
    """The page runs under script-src 'self': an inline <script> or on...= attribute in it would not run."""
    from footprint.pictures.folium_page import FRONTEND_DIR

    html = (FRONTEND_DIR / "index.html").read_text()
    assert inline_script_hashes(html) == []
    assert not re.search(r"\son[a-z]+\s*=", html, re.I) and "javascript:" not in html

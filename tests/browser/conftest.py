"""The real service and Debian's chromium, for the map page's browser tests.

Once per test module: the service on a free port of 127.0.0.1 with a new SQLite file and one Dask worker (as
`footprint serve` runs it), seeded with one footprint by a real job; then chromium through Playwright. Nothing
here reaches the internet: chromium runs with its background networking off, and the tests assert that every
request the page makes goes to the service."""

import io
import json
import os
import socket
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from contextlib import contextmanager
from pathlib import Path
from urllib.parse import urlparse

import numpy as np
import pytest

from tests.authorities.report import table2_entry, table2_stop

ROOT = Path(__file__).resolve().parents[2]
CHROMIUM = Path("/usr/bin/chromium")
# the tests' screenshots: the tracked docs/figures are rewritten only when asked (FOOTPRINT_WRITE_FIGURES=1, as a
# figure run does); a test run writes to a temporary folder and leaves the checkout as it was
FIGURES_DIR = (
    ROOT / "docs" / "figures"
    if os.environ.get("FOOTPRINT_WRITE_FIGURES") == "1"
    else Path(tempfile.mkdtemp(prefix="footprint-figures-"))
)
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
START_TIMEOUT_S = 600.0  # migrations, the Dask cluster and the first compile of the flight kernel
JOB_TIMEOUT_S = 600.0
WAIT_MS = 120_000  # every wait for the page (Playwright's default too): a loaded machine is slow, not wrong

# A single-parameter footprint of 4 bank settings (7 trajectories with the mirror), entered at 150 E heading
# north-east: its boundary crosses longitude 180, so the tests also see the map unwrap it.
SEED_ENTRY = table2_entry(heading_deg=60.0, latitude_deg=28.5, longitude_deg=150.0)
SEED_JOB = {
    "kind": "footprint",
    "name": "lod-1.89, 4 banks, 150E",
    "study": {
        "case": {
            "vehicle": {"builtin": "lod-1.89"},
            "entry": SEED_ENTRY,
            "alpha": {"law": "max_ld"},
            "bank_start": "pullout",
            "stop": table2_stop(),
        },
        "method": "single_parameter",
        "bank0_deg": [0, 45, 90, 135],
        "mirror": True,
    },
}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Service:
    def __init__(self, base_url: str):
        self.base_url = base_url

    def call(self, path: str, body=None, method=None):
        data = None if body is None else json.dumps(body).encode()
        req = urllib.request.Request(
            self.base_url + path,
            data=data,
            method=method or ("POST" if data else "GET"),
            headers={"Content-Type": "application/json"},
        )
        with urllib.request.urlopen(req, timeout=60) as res:
            return json.loads(res.read() or b"null")

    def run_job(self, job: dict) -> dict:
        job_id = self.call("/api/jobs", job)["id"]
        deadline = time.monotonic() + JOB_TIMEOUT_S
        while time.monotonic() < deadline:
            state = self.call(f"/api/jobs/{job_id}")
            if state["status"] in ("succeeded", "failed", "cancelled"):
                assert state["status"] == "succeeded", state
                return state
            time.sleep(0.3)
        raise TimeoutError(f"job {job_id} did not finish in {JOB_TIMEOUT_S} s")


@contextmanager
def running_service(folder: Path, **env):
    """The service on a free port with a new SQLite file in folder and one Dask worker; env overrides settings."""
    port = _free_port()
    env = (
        os.environ
        | {
            "FOOTPRINT_DATABASE_URL": f"sqlite:///{folder / 'footprint.db'}",
            "FOOTPRINT_DASK_WORKERS": "1",
            "FOOTPRINT_HOST": "127.0.0.1",
            "FOOTPRINT_PORT": str(port),
            "FOOTPRINT_API_TOKEN": "",
            "FOOTPRINT_TILE_URL": "",
        }
        | env
    )
    log = open(folder / "service.log", "w")
    code = (
        "import uvicorn\nfrom footprint.service.app import create_app\nfrom footprint.service.settings import "
        "load_settings\ns = load_settings()\nuvicorn.run(create_app(s), host=s.host, port=s.port, log_level='warning')"
    )
    proc = subprocess.Popen([sys.executable, "-c", code], cwd=folder, env=env, stdout=log, stderr=subprocess.STDOUT)
    svc = Service(f"http://127.0.0.1:{port}")
    try:
        deadline = time.monotonic() + START_TIMEOUT_S
        while True:
            try:
                if svc.call("/api/health")["status"] == "ok":
                    break
            except (urllib.error.URLError, ConnectionError, OSError):
                pass
            if proc.poll() is not None or time.monotonic() > deadline:
                log.flush()
                pytest.fail(f"the service did not start:\n{(folder / 'service.log').read_text()[-3000:]}")
            time.sleep(0.3)
        yield svc
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
        log.close()


@pytest.fixture(scope="module")
def service(tmp_path_factory):
    """The running service, seeded: .base_url, .footprint (the seeded footprint as GET /api/footprints/{id})."""
    if not (ROOT / "frontend" / "vendor" / "leaflet" / "leaflet.js").exists():
        pytest.fail("frontend/vendor is missing: run `npm ci` in frontend/ (it copies the libraries there)")
    with running_service(tmp_path_factory.mktemp("service")) as svc:
        job = svc.run_job(SEED_JOB)
        svc.footprint = svc.call(job["result"]["footprints"][0])
        yield svc


@pytest.fixture(scope="module")
def browser():
    if not CHROMIUM.exists():
        missing = "Debian's chromium is not installed (apt-get install -y chromium; .ci/run does)"
        if os.environ.get("FOOTPRINT_REQUIRE_BROWSER") == "1":  # CI: a skipped browser test is a failure
            pytest.fail(missing)
        pytest.skip(missing)
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS, headless=True)
        new_context = b.new_context

        def patient_context(**options):
            context = new_context(**options)
            context.set_default_timeout(WAIT_MS)  # for the waits a test does not time itself (30 s otherwise)
            return context

        b.new_context = patient_context
        yield b
        b.close()


# Content-Security-Policy violations, kept by the page itself (Playwright's init scripts are exempt from the CSP)
RECORD_VIOLATIONS_JS = """window.__violations = [];
document.addEventListener("securitypolicyviolation",
  (e) => window.__violations.push(`${e.effectiveDirective} blocked ${e.blockedURI || "inline"}`));"""


class PageRun:
    """A page with every request, every script error and every CSP violation recorded."""

    def __init__(self, page):
        self.page, self.requests, self.errors = page, [], []
        page.add_init_script(RECORD_VIOLATIONS_JS)
        page.on("request", lambda r: self.requests.append(r.url))
        page.on("pageerror", lambda e: self.errors.append(str(e)))
        page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)

    def violations(self) -> list[str]:
        return self.page.evaluate("() => window.__violations")


@pytest.fixture
def open_page(browser, service):
    """open_page(width=1280, height=800) -> PageRun, the page loaded and its first footprints drawn."""
    contexts = []

    def opener(width=1280, height=800):
        context = browser.new_context(viewport={"width": width, "height": height}, accept_downloads=True)
        contexts.append(context)
        run = PageRun(context.new_page())
        run.page.goto(service.base_url + "/")
        run.page.wait_for_selector("body[data-ready=true]", timeout=WAIT_MS)
        return run

    yield opener
    for c in contexts:
        c.close()


def pytest_terminal_summary(terminalreporter):
    """Say loudly, at the end, that the browser tests did not run when chromium is missing."""
    if CHROMIUM.exists():
        return
    skipped = [r for r in terminalreporter.stats.get("skipped", []) if "tests/browser/" in str(r.nodeid)]
    if skipped:
        terminalreporter.write_sep(
            "!",
            f"{len(skipped)} browser tests SKIPPED: chromium not found at {CHROMIUM}; "
            "install with `apt-get install chromium`",
            red=True,
            bold=True,
        )


# The PNG export's part of the map (exporting.js worldCrop): latitudes -90..90 and one turn of longitude about the
# view's centre, within the view, in the container's CSS px. Said here as the export's contract: a test maps a place
# to the PNG's pixel through it.
PNG_CROP_JS = """() => { const m = window.footprintApp.mapView.map, s = m.getSize(), c = m.getCenter().lng;
  const at = (a, o) => m.latLngToContainerPoint([a, o]);
  const x = Math.max(0, Math.floor(at(0, c - 180).x)), y = Math.max(0, Math.floor(at(90, c).y));
  return {x, y, w: Math.min(s.x, Math.ceil(at(0, c + 180).x)) - x, h: Math.min(s.y, Math.ceil(at(-90, c).y)) - y}; }"""


PNG_PIXEL_RATIO = 2  # exporting.js PIXEL_RATIO
COLOR_TOLERANCE = 8  # per channel, 0-255: the antialiasing and rounding of a canvas blend


def close(a, b, tolerance=COLOR_TOLERANCE):
    """Two colours alike within tolerance per channel."""
    return bool(np.all(np.abs(np.array(a, float) - np.array(b, float)) <= tolerance))


def over(background, rgb, alphas):
    """A colour painted over background at each opacity in turn (the confidence levels, one over the other)."""
    out = np.array(background, float)
    for a in alphas:
        out = out * (1 - a) + np.array(rgb) * a
    return out


def hex_rgb(color: str) -> tuple[int, int, int]:
    """#rrggbb as (r, g, b)."""
    return int(color[1:3], 16), int(color[3:5], 16), int(color[5:7], 16)


def pixels_like(image, rgb, tolerance=30):
    """How many pixels of the image are within tolerance (per channel) of a colour: a line's, antialiased."""
    return int(np.all(np.abs(np.asarray(image, float) - rgb) <= tolerance, axis=-1).sum())


def download(page, selector):
    """Click what downloads a file: (its suggested name, its bytes)."""
    with page.expect_download() as info:
        page.click(selector)
    return info.value.suggested_filename, Path(info.value.path()).read_bytes()


def png_export(page):
    """The page's PNG export of its view, as an RGB image."""
    from PIL import Image

    return Image.open(io.BytesIO(download(page, "#export-png")[1])).convert("RGB")


def refusal(service, path, body):
    """The service's own 422 for a body: its {detail, field}."""
    req = urllib.request.Request(
        service.base_url + path, json.dumps(body).encode(), {"Content-Type": "application/json"}
    )
    with pytest.raises(urllib.error.HTTPError) as info:
        urllib.request.urlopen(req, timeout=60)
    assert info.value.code == 422
    return json.loads(info.value.read())


def only_the_service(run, service):
    hosts = {urlparse(u).hostname for u in run.requests if not u.startswith(("data:", "blob:"))}
    assert hosts == {urlparse(service.base_url).hostname}, hosts

"""Issue 15 item 5: with no token set (the default), another site's page could write: chromium created a site here
with a cross-site text/plain POST to /api/sites/csv (a "simple" request, no CORS preflight to refuse). Writes now
come from this service's own pages, an allowed origin (FOOTPRINT_CORS_ORIGINS) or a tool (no Origin), and the CSV
upload reads only text/csv."""

CSV = "name,latitude_deg,longitude_deg\nKSC,28.6,-80.6\n"
EVIL = {"Origin": "https://evil.example"}


def site_names(api) -> list[str]:
    return [s["name"] for s in api.get("/api/sites").json()]


def test_a_cross_site_or_plain_text_write_stores_nothing(api):
    before = site_names(api)
    plain = api.post("/api/sites/csv", content=CSV, headers={"Content-Type": "text/plain"})
    assert plain.status_code == 415 and plain.json()["detail"].startswith("body: the sites are a text/csv body")
    cross = api.post("/api/sites/csv", content=CSV, headers={"Content-Type": "text/csv"} | EVIL)
    assert cross.status_code == 403 and "cross-site write refused" in cross.json()["detail"]
    json_cross = api.post("/api/sites", json={"name": "x", "latitude_deg": 0, "longitude_deg": 0}, headers=EVIL)
    assert json_cross.status_code == 403
    assert api.post("/api/jobs", json={"kind": "footprint", "study": {}}, headers=EVIL).status_code == 403
    assert site_names(api) == before


def test_the_services_own_page_and_tools_still_write(api):
    own = api.post("/api/sites/csv", content=CSV, headers={"Content-Type": "text/csv", "Origin": "http://testserver"})
    assert own.status_code == 201, own.text
    tool = api.post("/api/sites/csv", content=CSV, headers={"Content-Type": "text/csv; charset=utf-8"})
    assert tool.status_code == 201, tool.text
    for s in api.get("/api/sites").json():
        if s["name"] == "KSC":
            api.delete(f"/api/sites/{s['id']}")

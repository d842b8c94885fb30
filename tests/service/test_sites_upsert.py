"""Issue 53 item 5: the same CSV of sites uploaded again duplicated every site (23 sites for 20 names, the reach
then said "17 of 23"); sites are kept by name now, and every site can be removed at once."""

CSV = "text/csv"
SITES = "name,latitude_deg,longitude_deg\nEdwards AFB,34.9,-117.9\nKSC,28.6,-80.6\nWoomera,-31.2,136.8\n"


def upload(api, text):
    r = api.post("/api/sites/csv", content=text, headers={"content-type": CSV})
    assert r.status_code == 201, r.text
    return r.json()


def stored(api):
    return {s["name"]: s for s in api.get("/api/sites").json()}


def test_the_same_csv_uploaded_again_adds_no_site_and_a_moved_row_moves_its_site(api):
    assert api.delete("/api/sites").status_code == 200
    assert upload(api, SITES) == {"created": 3, "updated": 0}
    first = stored(api)
    assert upload(api, SITES) == {"created": 0, "updated": 3}
    again = stored(api)
    assert again == first  # the same ids, places and verdicts: nothing duplicated
    # a row of a stored name moves that site (by id); a new name is added; a name given twice keeps its last row
    moved = SITES.splitlines()[0] + "\nKSC,28.5,-80.7\nKwajalein,9.4,167.5\nKwajalein,8.7,167.7\n"
    assert upload(api, moved) == {"created": 1, "updated": 1}
    now = stored(api)
    assert len(now) == 4 and now["KSC"]["id"] == first["KSC"]["id"]
    assert (now["KSC"]["latitude_deg"], now["KSC"]["longitude_deg"]) == (28.5, -80.7)
    assert (now["Kwajalein"]["latitude_deg"], now["Kwajalein"]["longitude_deg"]) == (8.7, 167.7)
    assert len(api.get("/api/sites").json()) == 4


def test_every_site_is_removed_at_once(api):
    upload(api, SITES)
    count = len(api.get("/api/sites").json())
    assert count >= 3
    r = api.delete("/api/sites")
    assert r.status_code == 200 and r.json() == {"deleted": count}
    assert api.get("/api/sites").json() == []
    assert api.delete("/api/sites").json() == {"deleted": 0}

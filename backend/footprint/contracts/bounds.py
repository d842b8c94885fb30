"""The one table of text bounds: every text a request can write to a database column is bounded by its column's
length here. The contracts bound their fields with these constants, the service's models size their String columns
with them, and tests/service/test_text_bounds.py checks the migrations against TEXT_COLUMNS."""

VEHICLE_ID_CHARS = 64  # a stored vehicle's id (POST /api/vehicles; {"stored": id} in a case)
VEHICLE_NAME_CHARS = 200  # an inline vehicle's `name`: a footprint's `vehicle`
JOB_NAME_CHARS = 200  # a job's `name`, or the footprint study's default name
FOOTPRINT_NAME_CHARS = 300  # a footprint's name: its job's name, a rename, or a sweep's derived name
SITE_NAME_CHARS = 200  # a landing site's name
PROGRESS_NOTE_CHARS = 200  # what a running job is doing (the core's note, cut to fit)

# column -> its bound (the request fields that write it use the same constant)
TEXT_COLUMNS = {
    ("vehicles", "id"): VEHICLE_ID_CHARS,
    ("footprints", "vehicle"): VEHICLE_NAME_CHARS,
    ("jobs", "name"): JOB_NAME_CHARS,
    ("footprints", "name"): FOOTPRINT_NAME_CHARS,
    ("sites", "name"): SITE_NAME_CHARS,
    ("jobs", "progress_note"): PROGRESS_NOTE_CHARS,
}

ELLIPSIS = "…"


def fitted(head: str, tail: str, chars: int) -> str:
    """`head tail` in at most `chars` characters: a derived name (a vehicle's name, then what tells its footprints
    apart) keeps its tail whole and cuts its head, marked by an ellipsis, so it fits the column it is written to."""
    room = chars - len(tail) - 1
    if len(head) > room:
        head = head[: max(room - len(ELLIPSIS), 0)] + ELLIPSIS
    return f"{head} {tail}"[:chars]

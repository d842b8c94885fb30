"""GET /api/vehicles with 1,000 stored custom vehicles (issue 15 item 8: a 64-entry cache of rebuilt vehicles,
walked in order, took 1.1-1.4 s a request past 64). Target: <= 100 ms.

The service runs in this process (FastAPI's TestClient: ASGI, no sockets) on a SQLite file and a one-worker local
cluster. Baseline, in the same process: the list as it was built before, every stored vehicle rebuilt from its
definition and its (L/D)max searched again, each request.

    python3 bench/bench_vehicles.py      # prints the figures, writes bench/results/vehicles.json
"""

import tempfile

from _timing import median_ms, save_result

VEHICLES = 1_000
TARGET_MS = 100.0


def glider(i: int) -> dict:
    """A small custom vehicle, each with its own L/D (a constant-coefficient aero model)."""
    return {"aero": {"constant": {"cl": 0.5, "cd": 0.5 / (1.0 + i / VEHICLES)}}, "wing_loading_psf": 40 + i % 30}


def main():
    from fastapi.testclient import TestClient

    from footprint.service.app import create_app
    from footprint.service.db import queries as q
    from footprint.service.routers import vehicles
    from footprint.service.settings import load_settings

    with tempfile.TemporaryDirectory() as tmp:
        app = create_app(load_settings(database_url=f"sqlite:///{tmp}/bench.db", dask_workers=1))
        with TestClient(app) as client:
            for i in range(VEHICLES):
                r = client.post("/api/vehicles", json={"id": f"glider-{i:04d}", "vehicle": glider(i)})
                assert r.status_code == 201, r.text
            listed = client.get("/api/vehicles").json()
            assert sum(not v["builtin"] for v in listed) == VEHICLES
            stored_ms = median_ms(lambda: client.get("/api/vehicles"), 7)

            def rebuilt():  # the list before: every vehicle rebuilt and summarized again
                with app.state.read_sessions.begin() as session:
                    rows = q.list_vehicles(session)
                    return [vehicles._summary(vehicles._custom_vehicle(r.definition)) for r in rows]

            rebuilt_ms = median_ms(rebuilt, 3)
    out = {
        "vehicles": VEHICLES,
        "list_ms": round(stored_ms, 1),
        "baseline_rebuilt_ms": round(rebuilt_ms, 1),
        "speedup": round(rebuilt_ms / stored_ms, 1),
        "target_ms": TARGET_MS,
        "within_target": stored_ms <= TARGET_MS,
    }
    save_result("vehicles", out)
    print(
        f"GET /api/vehicles with {VEHICLES} custom vehicles: {stored_ms:.1f} ms (target <= {TARGET_MS:g} ms: "
        f"{'met' if out['within_target'] else 'NOT met'}); rebuilding them as before: {rebuilt_ms:.0f} ms "
        f"({out['speedup']}x)"
    )


if __name__ == "__main__":
    main()

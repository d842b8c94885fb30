"""The doors against the kernel (issue 29 item 3): one trajectory (the Table 2 case, lod-2.2) flown by the compiled
integrator alone (trajectory._fly: the parameters packed, the entry state, the integration), by simulate(spec)
(histories and summary), by footprint.api.fly(dict) (the case parsed, its spec built, flown) and by POST
/api/trajectories through the service's ASGI app in this process (FastAPI's TestClient, SQLite in a temporary
folder), all in the same process; each the fastest of 7 repeats of a batch. The target: every door within 30 % of
the kernel.

    python3 bench/bench_doors.py   # bench/results/doors.json
"""

import json
import os
import tempfile
import time
from pathlib import Path

from _timing import save_result

CASE = json.loads((Path(__file__).resolve().parents[1] / "examples" / "table2_lod22.json").read_text())


def fastest_ms(fn, n: int = 300, repeats: int = 7) -> float:
    for _ in range(20):
        fn()
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        best = min(best, (time.perf_counter() - t0) / n)
    return 1e3 * best


def main() -> None:
    from footprint import api
    from footprint.contracts import parse
    from footprint.core.trajectory import _fly, simulate

    spec = parse("case", CASE).to_spec()
    kernel = fastest_ms(lambda: _fly(spec))
    doors = {"simulate(spec)": fastest_ms(lambda: simulate(spec)), "api.fly(dict)": fastest_ms(lambda: api.fly(CASE))}
    with tempfile.TemporaryDirectory() as folder:
        os.environ["FOOTPRINT_DATABASE_URL"] = f"sqlite:///{folder}/bench.db"
        from fastapi.testclient import TestClient

        from footprint.service.app import create_app
        from footprint.service.settings import load_settings

        with TestClient(create_app(load_settings(), runs_jobs=False)) as client:
            doors["POST /api/trajectories"] = fastest_ms(lambda: client.post("/api/trajectories", json=CASE), n=100)
    data = {
        "kernel_ms": kernel,
        "doors_ms": doors,
        "over_kernel": {k: v / kernel - 1.0 for k, v in doors.items()},
        "target_over_kernel": 0.30,
        "load": os.getloadavg()[0],
    }
    print(json.dumps(data, indent=2))
    print(save_result("doors", data))


if __name__ == "__main__":
    main()

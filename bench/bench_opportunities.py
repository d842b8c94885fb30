"""Landing opportunities (issue 28): one day of opportunities for the 20 sites of examples/reach_20_sites.json from
the ISS's published element set (51.6 deg, 15.7 revolutions a day; examples/opportunities_iss_20_sites.json), on a
LocalCluster of 2 workers, against today's `reach` of the same footprint study, sites and 24 hours (its circular
orbit at the ISS's inclination and height) in the same process. Each run twice: the first loads the workers' caches.
Also with `"refly": "none"` (the scan's footprints only) and `"full"` (each footprint flown whole again). The
1-minute load average is recorded.

    python3 bench/bench_opportunities.py   # bench/results/opportunities.json
"""

import copy
import os
import time

from _timing import example, save_result

TARGET_S = 5.0


def load() -> float:
    return round(os.getloadavg()[0], 2)


def reach_request(study: dict) -> dict:
    """Today's reach for the same footprint, sites and hours: a circular orbit of the TLE's inclination and height."""
    footprint = copy.deepcopy(study["footprint"])
    return {
        "footprint": {"study": footprint},
        "orbit": {"inclination_deg": 51.6416, "altitude_nmi": 190.0, "node_longitude_deg": 0.0},
        "sites": study["sites"],
        "revolutions": {"first": 1, "hours": 24},
        "u_step_deg": 1.0,
        "earth_rotation": "none",
    }


def timed(kind: str, request: dict, client) -> tuple[float, dict]:
    """The second of two runs (the first loads the workers' numba caches), its request new to the workers (they keep
    a request's parse and what it made, e.g. the scan's footprints, for its later parts)."""
    from footprint import parallel

    parallel.run(kind, request | {"description": "warm"}, client=client)
    t0 = time.perf_counter()
    result = parallel.run(kind, request | {"description": "timed"}, client=client)
    return time.perf_counter() - t0, result


def main() -> None:
    from footprint.parallel import start_client

    study = example("opportunities_iss_20_sites")
    before = load()
    client, close = start_client(workers=2)
    try:
        seconds, result = timed("opportunities", study, client)
        scan_s, scan = timed("opportunities", study | {"refly": "none"}, client)
        full_s, _ = timed("opportunities", study | {"refly": "full"}, client)
        reach_s, _ = timed("reach", reach_request(study), client)
    finally:
        close()
    data = {
        "opportunities_s": seconds,
        "opportunities_scan_only_s": scan_s,
        "opportunities_full_refly_s": full_s,
        "reach_s": reach_s,
        "ratio_to_reach": seconds / reach_s,
        "ratio_scan_only_to_reach": scan_s / reach_s,
        "target_s": TARGET_S,
        "revolutions": result["run"]["tasks"],
        "opportunities": len(result["opportunities"]),
        "meeting_rules": sum(o["meets_rules"] for o in result["opportunities"]),
        "scan_only_opportunities": len(scan["opportunities"]),
        "load_before": before,
        "load_after": load(),
    }
    print(data)
    print(save_result("opportunities", data))


if __name__ == "__main__":
    main()

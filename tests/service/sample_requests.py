"""Sample requests for the service tests: small studies (each footprint flies in well under a second), one
long one, a reach and a sweep."""

import copy

from tests.authorities.report import table2_entry, table2_stop

CASE = {
    "vehicle": {"builtin": "lod-1.89"},
    "entry": {
        "altitude_ft": 364_800,
        "velocity_fps": 22_000,
        "gamma_deg": -3,
        "heading_deg": 90,
        "latitude_deg": 10,
        "longitude_deg": 0,
    },
    "stop": {"altitude_ft": 50_000},
}
UNKNOWN_ID = "0f0e0f0e-0f0e-4f0e-8f0e-0f0e0f0e0f0e"  # a well-formed id that no job or footprint has
FOOTPRINT = {"case": CASE, "method": "single_parameter", "bank0_deg": [0, 45, 90]}  # spans 11-83 deg E
# the Table 2 entry: reaches 14,869 nmi, past half the circumference (pi R' = 10,807 nmi)
LONG_FOOTPRINT = {
    "case": {
        "vehicle": {"builtin": "lod-1.89"},
        "entry": table2_entry(),
        "alpha": {"law": "max_ld"},
        "bank_start": "pullout",
        "stop": table2_stop(),
    },
    "method": "single_parameter",
    "bank0_deg": [0, 60, 120],
}
# the true optimal boundary of a small problem: Betts' shuttle (polynomial aero, non-rotating sphere, both
# halves by reflection), 3 down-ranges, 3 g: six IPOPT solves, ~8 s
SHUTTLE = {
    "name": "Space Shuttle (Betts 2010, sec. 6.1)",
    "weight_lb": 203000,
    "reference_area_ft2": 2690,
    "aero": {
        "polynomial": {
            "cl": [-0.20704, 0.029244],
            "cd": [0.07854, -0.0061592, 0.000621408],
            "alpha_range_deg": [-90, 90],
        }
    },
}
OPTIMAL_FOOTPRINT = {
    "case": {
        "vehicle": SHUTTLE,
        "planet": {"rotating": False, "oblate": False},
        "entry": {
            "altitude_ft": 260_000,
            "velocity_fps": 25_600,
            "gamma_deg": -1,
            "heading_deg": 90,
            "latitude_deg": 0,
            "longitude_deg": 0,
        },
        "alpha": {"law": "constant", "alpha_deg": 17},
        "stop": {"altitude_ft": 80_000},
    },
    "method": "collocation",
    "points_per_half": 3,
    "max_load_factor": 3,
    "alpha_bounds_deg": [8, 90],  # the polynomial's lift positive: upright (unbounded: upside down, at 6x the time)
}


def footprint_study(**entry) -> dict:
    """FOOTPRINT with some entry fields changed."""
    study = copy.deepcopy(FOOTPRINT)
    study["case"]["entry"] |= entry
    return study


SWEEP = {
    "name": "tiny",
    "base": {"entry": {"altitude_ft": 364_800, "heading_deg": 90}, "stop": {"altitude_ft": 50_000}},
    "method": "single_parameter",
    "bank0_deg": [0, 90],
    "vehicles": ["lod-1.89"],
    "entry_velocity_fps": [20_000, 22_000],
    "entry_gamma_deg": [-3],
    "velocity_frame": "relative",
}
OPTIMIZE = {"case": CASE, "payoff": {"quantity": "crossrange_nmi", "goal": "max"}, "max_trajectories": 20}
REACH_POINTS = [
    {"downrange_nmi": d, "crossrange_nmi": c, "flight_time_s": t}
    for d, c, t in ((2_000, 0, 1_500), (3_000, 600, 2_000), (4_000, 0, 2_500), (3_000, -600, 2_000))
]
REACH = {
    "footprint": {"points": REACH_POINTS},
    "orbit": {"inclination_deg": 28.5, "altitude_nmi": 150, "node_longitude_deg": 0},
    "sites": [
        {"name": "KSC", "latitude_deg": 28.6, "longitude_deg": -80.6},
        {"name": "Edwards", "latitude_deg": 34.9, "longitude_deg": -117.9},
    ],
    "revolutions": {"first": 1, "last": 3},
    "u_step_deg": 2.0,
}

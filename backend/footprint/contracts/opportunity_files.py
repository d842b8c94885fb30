"""The files a planner hands on of one opportunity (issue 52): its coast and entry (core.opportunity_path) as a CCSDS
Orbit Ephemeris Message (CCSDS 502.0-B-2, written and read by the ccsds-ndm package, KVN or XML) and as CZML for
Cesium (written by the czml3 package). The opportunity is named by its index in the answer's `opportunities` (landing
order, as the page's table and the CSV list them).
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from footprint.contracts.opportunities import OpportunitiesStudy
from footprint.core import opportunity_path as path
from footprint.core.constants import FT_PER_M
from footprint.core.elements import FT_PER_KM, earth_fixed_to_teme
from footprint.core.errors import InputError
from footprint.core.opportunities import Flier
from footprint.core.utc import after_s, iso, isos, parse_iso

OemFormat = Literal["kvn", "xml"]


def opportunity_at(answer: dict[str, Any], index: int) -> dict[str, Any]:
    """The answer's opportunity at `index` (0: the first to land), or InputError naming `opportunity`."""
    found = answer["opportunities"]
    if not 0 <= index < len(found):
        allowed = f"0 to {len(found) - 1}" if found else "none: the answer has no opportunity"
        raise InputError("opportunity", f"{index} is outside the allowed range of {allowed}")
    chosen: dict[str, Any] = found[index]
    return chosen


def phases(study: OpportunitiesStudy, o: dict[str, Any]) -> tuple[path.Phase, path.Phase]:
    """The opportunity's coast (its burn and Δv on the study's orbit) and its entry (the study's case from there)."""
    coast, entry_row = path.coast_phase(study.orbit, study.coast, parse_iso(o["burn_utc"]), o["delta_v_fps"])
    spec = Flier(study.spec, study.footprint.to_settings()).at_entry(entry_row)
    return coast, path.entry_phase(spec, float(entry_row[0]))


def _epochs(burn: datetime, seconds: NDArray[np.float64]) -> list[str]:
    """CCSDS epochs (ISO 8601 without the zone: TIME_SYSTEM says UTC) to the millisecond; 23:59:60 in a leap second."""
    return [t.removesuffix("Z") for t in isos(after_s(burn, seconds))]


def _oem_segment(
    name: str, frame: str, about: str, epochs: list[str], r_km: Any, v_km_s: Any, meta: dict[str, str]
) -> Any:
    from ccsds_ndm.models.ndmxml2 import OemData, OemMetadata, OemSegment, StateVectorAccType
    from ccsds_ndm.models.ndmxml2.ndmxml_2_0_0_common_2_0 import (
        PositionType,
        PositionUnits,
        VelocityType,
        VelocityUnits,
    )

    def km(x: float) -> PositionType:
        return PositionType(value=float(x), units=PositionUnits.KM)

    def km_s(x: float) -> VelocityType:
        return VelocityType(value=float(x), units=VelocityUnits.KM_S)

    states = [
        StateVectorAccType(
            epoch=e, x=km(r[0]), y=km(r[1]), z=km(r[2]), x_dot=km_s(v[0]), y_dot=km_s(v[1]), z_dot=km_s(v[2])
        )
        for e, r, v in zip(epochs, r_km, v_km_s)
    ]
    metadata = OemMetadata(
        comment=[f"{name}: {about}"], center_name="EARTH", ref_frame=frame, time_system="UTC",
        start_time=epochs[0], stop_time=epochs[-1], **meta,
    )  # fmt: skip
    return OemSegment(metadata=metadata, data=OemData(state_vector=states))


def opportunity_oem(
    study: OpportunitiesStudy,
    answer: dict[str, Any],
    index: int,
    data_format: OemFormat = "kvn",
    made_utc: datetime | None = None,
) -> str:
    """The opportunity's OEM: a segment for the coast in TEME (the orbit's own frame, SGP4's: a planner compares it
    with the elements' ephemeris) and one for the entry in GRC (Greenwich rotating, polar motion neglected: the
    rotating earth the flight is flown on, its velocity relative to the earth); km and km/s, epochs in UTC."""
    from ccsds_ndm.models.ndmxml2 import NdmHeader, Oem, OemBody
    from ccsds_ndm.ndm_io import NDMFileFormats, NdmIo

    o = opportunity_at(answer, index)
    coast, entry = phases(study, o)
    burn, elements = parse_iso(o["burn_utc"]), answer["elements"]
    number = elements["satellite_number"]
    meta = {
        "object_name": elements["name"] or f"satellite {number or 'unnumbered'}",
        "object_id": str(number or "UNKNOWN"),  # the catalogue number: the elements carry no international designator
    }
    coast_utc = after_s(burn, coast.seconds)
    r_teme, v_teme = earth_fixed_to_teme(coast.r_ft, coast.v_rel_fps, coast_utc, study.coast.omega_rad_s)
    segments = [
        _oem_segment(  # TEME: the coast is an orbit, in its elements' own frame (SGP4's), its velocity inertial
            "coast", "TEME", f"deorbit burn {o['delta_v_fps']:.3f} ft/s retrograde at {o['burn_utc']} to the entry "
            f"interface at {study.deorbit.interface_altitude_ft:,.0f} ft (vacuum, the orbit's earth's gravity)",
            _epochs(burn, coast.seconds), r_teme, v_teme, meta,
        ),
        _oem_segment(  # GRC: the entry is flown on the rotating earth (TEME turned by GMST, no polar motion)
            "entry", "GRC", f"the footprint study's case flown from the entry state to its stop, for {o['site_name']} "
            "(its own controls, not guided to the site); earth-fixed, the velocity relative to the earth",
            _epochs(burn, entry.seconds), entry.r_ft / FT_PER_KM, entry.v_rel_fps / FT_PER_KM, meta,
        ),
    ]  # fmt: skip
    header = NdmHeader(
        comment=[f"Footprint landing opportunity {index}: {o['site_name']}, revolution {o['revolution_number']}"],
        creation_date=iso(made_utc or datetime.now(UTC)).removesuffix("Z"),
        originator="Footprint",
    )
    oem = Oem(header=header, body=OemBody(segment=segments))
    fmt = NDMFileFormats.KVN if data_format == "kvn" else NDMFileFormats.XML
    text: str = NdmIo().to_string(oem, fmt)
    return text


def opportunity_czml(study: OpportunitiesStudy, answer: dict[str, Any], index: int) -> str:
    """The opportunity's CZML: a clock over the burn to the stop, and the vehicle's packet with its availability,
    its earth-fixed positions (m, Cesium's FIXED frame: the GRC states, polar motion under 20 m neglected) sampled
    in seconds from the burn, a path and a label; the site a point with its name."""
    from czml3 import CZML_VERSION, Clock, Document, Packet
    from czml3.enums import InterpolationAlgorithms
    from czml3.properties import Color, Label, Path, Point, PolylineMaterial, Position, SolidColorMaterial
    from czml3.types import IntervalValue, TimeInterval

    o = opportunity_at(answer, index)
    coast, entry = phases(study, o)
    burn = parse_iso(o["burn_utc"])
    seconds = np.concatenate([coast.seconds, entry.seconds[1:]])  # the entry's first state is the coast's last
    r_m = np.concatenate([coast.r_ft, entry.r_ft[1:]]) / FT_PER_M
    start, end = _epochs(burn, seconds[[0, -1]])
    start, end = start + "Z", end + "Z"
    name = f"{o['site_name']}, revolution {o['revolution_number']}"
    site = answer["sites"][o["site"]]
    samples = np.column_stack([seconds, r_m]).ravel().tolist()
    packets = [
        Packet(
            id="document", name=f"Footprint landing opportunity {index}: {name}", version=CZML_VERSION,
            clock=IntervalValue(start=start, end=end, value=Clock(currentTime=start, multiplier=10)),
        ),
        Packet(
            id=f"opportunity-{index}", name=name, availability=TimeInterval(start=start, end=end),
            description=f"burn {o['burn_utc']}, entry {o['entry_utc']}, landing {o['landing_utc']}; after the entry, "
            "the footprint study's case flown to its stop (its own controls, not guided to the site)",
            position=Position(epoch=start, referenceFrame="FIXED", cartesian=samples,
                              interpolationAlgorithm=InterpolationAlgorithms.LAGRANGE, interpolationDegree=5),
            path=Path(show=True, width=2, leadTime=0, trailTime=float(seconds[-1]) + 1.0, resolution=10,
                      material=PolylineMaterial(solidColor=SolidColorMaterial(color=Color(rgba=[230, 97, 0, 255])))),
            label=Label(show=True, text=name),
        ),
        Packet(
            id=f"site-{o['site']}", name=site["name"],
            position=Position(cartographicDegrees=[site["longitude_deg"], site["latitude_deg"], 0.0]),
            point=Point(show=True, pixelSize=8, color=Color(rgba=[0, 114, 178, 255])),
            label=Label(show=True, text=site["name"]),
        ),
    ]  # fmt: skip
    text: str = Document(packets=packets).to_json()
    return text

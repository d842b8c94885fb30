"""The files a planner hands on of one opportunity (issue 52): its coast and entry (core.opportunity_path) as a CCSDS
Orbit Ephemeris Message (CCSDS 502.0-B-2, written and read by the oem package, KVN or XML) and as CZML for Cesium
(written by the czml3 package). The entry is the flight guided to the opportunity's site (the answer's `guided`),
or, when the study asks for no guided flights, the footprint study's case on its own controls. The opportunity is
named by its index in the answer's `opportunities` (landing order, as the page's table and the CSV list them).
"""

from __future__ import annotations

import tempfile
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Literal
from xml.etree import ElementTree

import numpy as np
from numpy.typing import NDArray

from footprint.contracts.opportunities import OpportunitiesStudy
from footprint.core import deorbit as dorb
from footprint.core import opportunity_path as path
from footprint.core.constants import FT_PER_M
from footprint.core.elements import FT_PER_KM, earth_fixed_to_teme
from footprint.core.errors import InputError
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
    """The opportunity's coast (its burn and Δv on the study's orbit) and its entry from there: the case guided to the
    site (the spec the answer's `guided` flew, Flier.guided_flight), or the case's own flight without guided ones."""
    coast, entry_row = path.coast_phase(study.orbit, study.coast, parse_iso(o["burn_utc"]), o["delta_v_fps"])
    case = study.guided_specs()[o["site"]] if study.guided else study.spec
    return coast, path.entry_phase(dorb.entered(case, entry_row), float(entry_row[0]))


def _epochs(burn: datetime, seconds: NDArray[np.float64]) -> list[str]:
    """CCSDS epochs (ISO 8601 without the zone: TIME_SYSTEM says UTC) to the millisecond; 23:59:60 in a leap second."""
    return [t.removesuffix("Z") for t in isos(after_s(burn, seconds))]


def _oem_segment(frame: str, epochs: list[str], r_km: Any, v_km_s: Any, meta: dict[str, str]) -> Any:
    """One OEM segment (the oem package's): UTC epochs written back as given (astropy's strftime with a precision of
    3 writes the millisecond, and second 60 in a leap second), km and km/s."""
    from astropy.time import Time
    from oem.components import EphemerisSegment, MetaDataSection

    metadata = MetaDataSection(
        {"OBJECT_NAME": meta["object_name"], "OBJECT_ID": meta["object_id"], "CENTER_NAME": "EARTH",
         "REF_FRAME": frame, "TIME_SYSTEM": "UTC", "START_TIME": epochs[0], "STOP_TIME": epochs[-1]}
    )  # fmt: skip
    utc = Time(epochs, format="isot", scale="utc", precision=3)
    columns = np.column_stack([np.asarray(r_km, dtype=float), np.asarray(v_km_s, dtype=float)]).T
    return EphemerisSegment(metadata, (tuple(utc), *(tuple(c) for c in columns.tolist())))


def _written(segments: list[Any], made: str, data_format: OemFormat) -> str:
    """The message as the oem package writes it (its save_as, the one public writer, takes a path)."""
    from oem import CURRENT_VERSION, OrbitEphemerisMessage
    from oem.components import HeaderSection

    header = HeaderSection({"CCSDS_OEM_VERS": CURRENT_VERSION, "CREATION_DATE": made, "ORIGINATOR": "Footprint"})
    with tempfile.TemporaryDirectory() as folder:
        where = Path(folder) / f"opportunity.{data_format}"
        OrbitEphemerisMessage(header, segments).save_as(where, file_format=data_format)
        return where.read_text()


def _one_line(text: str) -> str:
    """A COMMENT's text on one line of printable characters (a site's name may hold line breaks or control
    characters: a KVN line would end there, and XML 1.0 allows none of them)."""
    return " ".join("".join(c if c.isprintable() else " " for c in text).split())


def _commented(text: str, data_format: OemFormat, header: str, segments: list[str]) -> str:
    """The message with its COMMENTs (which the oem package reads past but does not write), where CCSDS 502.0-B-2
    puts them: first in the header and first in each segment's metadata."""
    header, segments = _one_line(header), [_one_line(c) for c in segments]
    if data_format == "kvn":
        first, rest = text.split("\n", 1)
        parts = rest.split("META_START\n")
        out = f"{first}\nCOMMENT {header}\n{parts[0]}"
        return out + "".join(f"META_START\nCOMMENT {c}\n{p}" for c, p in zip(segments, parts[1:]))
    root = ElementTree.fromstring(text)
    for parent, comment in zip([root.find("header"), *root.iter("metadata")], [header, *segments]):
        assert parent is not None  # the oem package writes a header and a metadata per segment
        element = ElementTree.Element("COMMENT")
        element.text = comment
        parent.insert(0, element)
    ElementTree.indent(root)
    return ElementTree.tostring(root, encoding="unicode", xml_declaration=True) + "\n"


def _entry_about(study: OpportunitiesStudy, o: dict[str, Any]) -> str:
    """What the entry segment is: the flight guided to the site (the answer's `guided`), or the case's own."""
    if study.guided:
        g = o["guided"]
        held = "the vehicle's limits held" if g["limits_held"] else f"broke {', '.join(g['limits_broken'])}"
        return (f"the footprint study's case flown from the entry state guided to {o['site_name']} (the guided bank "
                f"law: the answer's guided flight, miss {g['guidance']['miss_nmi']:.2f} nmi, {held}) to the "
                "guidance's hand-over at its terminal energy")  # fmt: skip
    return (f"the footprint study's case flown from the entry state to its stop on its own controls (the study "
            f"asks for no guided flights: not guided to {o['site_name']})")  # fmt: skip


def opportunity_oem(
    study: OpportunitiesStudy,
    answer: dict[str, Any],
    index: int,
    data_format: OemFormat = "kvn",
    made_utc: datetime | None = None,
) -> str:
    """The opportunity's OEM (2.0): a segment for the coast in TEME (the orbit's own frame, SGP4's: a planner compares
    it with the elements' ephemeris) and one for the entry in GRC; km and km/s, epochs in UTC."""
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
        # TEME: the coast is an orbit, in its elements' own frame (SGP4's), its velocity inertial
        _oem_segment("TEME", _epochs(burn, coast.seconds), r_teme, v_teme, meta),
        # GRC, not ITRF: the integrator's earth is TEME turned by GMST about the pole, no polar motion (CCSDS's
        # Greenwich rotating frame); ITRF would claim the polar motion (under 20 m) applied
        _oem_segment("GRC", _epochs(burn, entry.seconds), entry.r_ft / FT_PER_KM, entry.v_rel_fps / FT_PER_KM, meta),
    ]
    comments = [
        f"coast: deorbit burn {o['delta_v_fps']:.3f} ft/s retrograde at {o['burn_utc']} to the entry interface at "
        f"{study.deorbit.interface_altitude_ft:,.0f} ft (vacuum, the orbit's earth's gravity)",
        f"entry: {_entry_about(study, o)}; earth-fixed, the velocity relative to the earth",
    ]
    made = iso(made_utc or datetime.now(UTC)).removesuffix("Z")
    text = _written(segments, made, data_format)
    title = f"Footprint landing opportunity {index}: {o['site_name']}, revolution {o['revolution_number']}"
    return _commented(text, data_format, title, comments)


def opportunity_czml(study: OpportunitiesStudy, answer: dict[str, Any], index: int) -> str:
    """The opportunity's CZML: a clock over the burn to the entry's end, and the vehicle's packet with its availability,
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
            f"{_entry_about(study, o)}",
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

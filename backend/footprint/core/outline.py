"""A footprint's boundary as an area on a map of latitude and longitude (issue 13).

The boundary's edges are straight in the (down-range, cross-range) chart about the entry (AFWAL-TR-82-3036
eqs. 8-11, core.sphere), as footprints.area_nmi2 and reach.margins take them; drawn as straight lines of latitude and longitude instead,
the long edges of a footprint over a pole become chords between points far apart in longitude. So each edge
is sampled in the chart (every MAX_EDGE_NMI) and carried to latitude and longitude (sphere.latlon_from_ranges),
the longitudes kept continuous. A boundary that goes once round the earth's axis encloses a pole (which one,
reach.placement_margins says, in the chart): it is closed along that pole (latitude +-90 at both ends of the
360 deg it spans), so that a fill on the cylindrical map, a GeoJSON ring and an even-odd test in latitude and
longitude all hold the polar cap inside.
"""

from dataclasses import dataclass

import numpy as np

from footprint.core.reach import placement_margins
from footprint.core.sphere import Reference, latlon_from_ranges, unwrap_longitude

MAX_EDGE_NMI = 60.0  # chart length of an outline's edge (1 deg of arc): short beside any footprint's features


@dataclass(frozen=True)
class Outline:
    """A closed ring (first point not repeated) in latitude and continuous longitude (deg): neighbours never
    differ by more than 180 deg, so the ring is a plain polygon on the cylindrical map; `pole` is the pole it
    encloses ("north", "south", or None), its last two points then on that pole."""

    latitude_deg: np.ndarray
    longitude_deg: np.ndarray
    pole: str | None

    def to_dict(self) -> dict:
        return {"latitude_deg": self.latitude_deg.tolist(), "longitude_deg": self.longitude_deg.tolist(),
                "pole": self.pole}


def sampled_ring(downrange_nmi, crossrange_nmi, max_edge_nmi=MAX_EDGE_NMI):
    """The closed chart polygon with its edges cut into pieces of at most max_edge_nmi, closing point included."""
    d = np.append(np.asarray(downrange_nmi, float), downrange_nmi[0])
    c = np.append(np.asarray(crossrange_nmi, float), crossrange_nmi[0])
    pieces = np.maximum(1, np.ceil(np.hypot(np.diff(d), np.diff(c)) / max_edge_nmi)).astype(int)
    t = np.concatenate([np.arange(k) / k for k in pieces])
    edge = np.repeat(np.arange(len(pieces)), pieces)
    ds = np.append(d[edge] + t * (d[edge + 1] - d[edge]), d[-1])
    cs = np.append(c[edge] + t * (c[edge + 1] - c[edge]), c[-1])
    return ds, cs


def outline(downrange_nmi, crossrange_nmi, reference: Reference, max_edge_nmi=MAX_EDGE_NMI) -> Outline:
    """The outline of the boundary given by its points' flown down-range and cross-range (nmi, in order round
    the boundary) about `reference`, the entry point and heading they are measured from."""
    ds, cs = sampled_ring(downrange_nmi, crossrange_nmi, max_edge_nmi)
    lat, lon = latlon_from_ranges(ds, cs, reference.latitude_deg, reference.longitude_deg, reference.heading_deg)
    lon = unwrap_longitude(lon)
    turns = round((lon[-1] - lon[0]) / 360.0)  # the closing point is the first again: 0 or +-1 turns
    if turns == 0:
        return Outline(lat[:-1], lon[:-1], None)
    _, north = placement_margins(reference, downrange_nmi, crossrange_nmi, np.zeros(len(downrange_nmi)),
                                 [90.0], [0.0])
    pole_deg = 90.0 if north[0] else -90.0
    lat = np.concatenate([lat, [pole_deg, pole_deg]])
    lon = np.concatenate([lon, [lon[-1], lon[0]]])
    return Outline(lat, lon, "north" if north[0] else "south")

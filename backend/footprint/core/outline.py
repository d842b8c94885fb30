"""A footprint's boundary as an area on a map of latitude and longitude (issues 13 and 25).

The boundary's edges are straight in the (down-range, cross-range) chart about the entry (AFWAL-TR-82-3036
eqs. 8-11, core.sphere), as footprints.area_nmi2 and reach.margins take them; drawn as straight lines of latitude and
longitude instead, the long edges of a footprint over a pole become chords between points far apart in longitude. So
each edge is sampled in the chart (every MAX_EDGE_NMI, and finer where it sweeps through longitude near a pole) and
carried to latitude and longitude (sphere.latlon_from_ranges), the longitudes kept continuous: `latitude_deg`,
`longitude_deg`, the boundary's line.

The area is that ring's inside on the cylindrical map's one copy, -180 to 180 deg, decided by the ring alone: it is
wound with the footprint on its left (the chart polygon counter-clockwise: the chart, the sphere and the map all keep
orientation), cut where it crosses the antimeridian, and the pieces joined along the map's edge counter-clockwise
(the window clip of d3-geo's and of Weiler-Atherton), so that the map's top or bottom edge -- a pole -- is taken in
exactly when the footprint holds that pole. A ring that never crosses the antimeridian is the area's outer ring when
it runs counter-clockwise on the map, and otherwise a hole in the whole map: a footprint that holds both poles.
"""

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core.sphere import Reference, latlon_from_ranges, unwrap_longitude

MAX_EDGE_NMI = 60.0  # chart length of an outline's edge (1 deg of arc): short beside any footprint's features
MAX_EDGE_LON_DEG = 2.0  # an edge's longitude step: near a pole 60 nmi sweeps through tens of degrees
MAX_REFINE = 64  # at most this many pieces again for one such edge (a pass within metres of a pole stops here)
WINDOW_DEG = (-180.0, 180.0)  # the map's one copy, as GeoJSON wants it (RFC 7946 section 3.1.9)
POLES = {(True, True): "both", (True, False): "north", (False, True): "south", (False, False): None}


@dataclass(frozen=True)
class Outline:
    """A footprint on the cylindrical map. `latitude_deg`, `longitude_deg`: its boundary, a closed ring (first point
    not repeated) in continuous longitude (neighbours never more than 180 deg apart), the footprint on its left.
    `area`: the footprint within -180..180 deg as polygons, each [outer ring, holes...], each ring an (n, 2) array of
    (longitude, latitude) closed by its first point again: outer rings counter-clockwise, holes clockwise (RFC 7946
    section 3.1.6). `pole`: the poles it holds, "north", "south", "both" or None."""

    latitude_deg: NDArray[np.float64]
    longitude_deg: NDArray[np.float64]
    area: tuple[tuple[NDArray[np.float64], ...], ...]
    pole: str | None

    def to_dict(self) -> dict[str, Any]:
        return {
            "latitude_deg": self.latitude_deg.tolist(),
            "longitude_deg": self.longitude_deg.tolist(),
            "area": [[ring.tolist() for ring in polygon] for polygon in self.area],
            "pole": self.pole,
        }

    @classmethod
    def from_dict(cls, o: dict[str, Any]) -> "Outline":
        return cls(
            np.asarray(o["latitude_deg"], float),
            np.asarray(o["longitude_deg"], float),
            tuple(tuple(np.asarray(r, float) for r in polygon) for polygon in o["area"]),
            o["pole"],
        )

    def shifted(self, lon_deg: float) -> "Outline":
        """The boundary's line on another copy of the map (the area stays on its one copy)."""
        return Outline(self.latitude_deg, self.longitude_deg + lon_deg, self.area, self.pole)


def _closed(
    downrange_nmi: NDArray[np.float64], crossrange_nmi: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The chart polygon with its first point repeated last."""
    return (
        np.append(np.asarray(downrange_nmi, float), downrange_nmi[0]),
        np.append(np.asarray(crossrange_nmi, float), crossrange_nmi[0]),
    )


def sampled_ring(
    downrange_nmi: NDArray[np.float64], crossrange_nmi: NDArray[np.float64], pieces: NDArray[np.int_]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The closed chart polygon with edge j cut into pieces[j] equal parts, closing point included."""
    d, c = _closed(downrange_nmi, crossrange_nmi)
    t = np.concatenate([np.arange(k) / k for k in pieces])
    edge = np.repeat(np.arange(len(pieces)), pieces)
    ds = np.append(d[edge] + t * (d[edge + 1] - d[edge]), d[-1])
    cs = np.append(c[edge] + t * (c[edge + 1] - c[edge]), c[-1])
    return ds, cs


def outline(
    downrange_nmi: ArrayLike, crossrange_nmi: ArrayLike, reference: Reference, max_edge_nmi: float = MAX_EDGE_NMI
) -> Outline:
    """The outline of the boundary given by its points' flown down-range and cross-range (nmi, in order round
    the boundary) about `reference`, the entry point and heading they are measured from."""
    down, cross = np.asarray(downrange_nmi, float), np.asarray(crossrange_nmi, float)
    if _signed_area(down, cross) < 0.0:  # the footprint on the left: a counter-clockwise chart polygon
        down, cross = np.roll(down[::-1], 1), np.roll(cross[::-1], 1)  # the first point kept first
    lat, lon = _ring_on_map(down, cross, reference, max_edge_nmi)
    area, north, south = window_area(lat, lon)
    return Outline(lat[:-1], lon[:-1], area, POLES[north, south])


def _ring_on_map(
    down: NDArray[np.float64], cross: NDArray[np.float64], reference: Reference, max_edge_nmi: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The chart ring sampled and carried to latitude and continuous longitude (closing point included); an edge
    that sweeps more than MAX_EDGE_LON_DEG of longitude between samples is sampled again, finer."""
    d, c = _closed(down, cross)
    pieces = np.maximum(1, np.ceil(np.hypot(np.diff(d), np.diff(c)) / max_edge_nmi)).astype(int)
    for _ in range(2):  # the finer edges once: their sweep is then within MAX_EDGE_LON_DEG (or MAX_REFINE)
        ds, cs = sampled_ring(down, cross, pieces)
        lat, lon = latlon_from_ranges(ds, cs, reference.latitude_deg, reference.longitude_deg, reference.heading_deg)
        lon = unwrap_longitude(lon)
        edge = np.repeat(np.arange(len(pieces)), pieces)
        sweep = np.zeros(len(pieces))
        np.maximum.at(sweep, edge, np.abs(np.diff(lon)))
        finer = np.minimum(pieces * MAX_REFINE, np.ceil(pieces * sweep / MAX_EDGE_LON_DEG)).astype(int)
        if np.all(finer <= pieces):
            break
        pieces = np.maximum(pieces, finer)
    return lat, lon


def _signed_area(x: ArrayLike, y: ArrayLike) -> float:
    """Twice the shoelace area of a closed polygon (first point not repeated): positive counter-clockwise."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    return float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _edge_position(x: float, y: float) -> float:
    """Where a point on the window's edge lies going counter-clockwise round it from its south-west corner: 0-1
    the bottom (the south pole), 1-2 the east edge, 2-3 the top (the north pole), 3-4 the west edge."""
    if x >= WINDOW_DEG[1]:
        return 1.0 + (y + 90.0) / 180.0
    return 3.0 + (90.0 - y) / 180.0  # arcs start and end on the east or west edge only


CORNERS = (
    (1.0, (WINDOW_DEG[1], -90.0)),
    (2.0, (WINDOW_DEG[1], 90.0)),
    (3.0, (WINDOW_DEG[0], 90.0)),
    (4.0, (WINDOW_DEG[0], -90.0)),
)


def window_area(
    latitude_deg: ArrayLike, longitude_deg: ArrayLike
) -> tuple[tuple[tuple[NDArray[np.float64], ...], ...], bool, bool]:
    """The inside (on its left) of a closed ring in continuous longitude (its last point its first, +-360 deg per
    turn round the axis) on the map's copy WINDOW_DEG: (polygons, holds the north pole, holds the south pole)."""
    lo, hi = WINDOW_DEG
    lat, lon = np.asarray(latitude_deg, float), np.asarray(longitude_deg, float)
    k = np.floor((lon - lo) / (hi - lo)).astype(int)  # the copy each point lies on
    x = lon - (hi - lo) * k
    cuts = np.nonzero(np.diff(k))[0]
    if cuts.size == 0:
        ring = np.column_stack([x, lat])
        if _signed_area(x[:-1], lat[:-1]) > 0.0:
            return ((ring,),), False, False
        world = np.array([[lo, -90.0], [hi, -90.0], [hi, 90.0], [lo, 90.0], [lo, -90.0]])
        return ((world, ring),), True, True
    arcs = _arcs(lat, lon, k, x, cuts)
    return _joined(arcs)


def _arcs(
    lat: NDArray[np.float64],
    lon: NDArray[np.float64],
    k: NDArray[np.int_],
    x: NDArray[np.float64],
    cuts: NDArray[np.intp],
) -> list[NDArray[np.float64]]:
    """The ring cut where it crosses an edge of its copy: arcs of (x, lat) within the window, each from the edge
    to the edge."""
    lo, hi = WINDOW_DEG
    width = hi - lo
    pieces: list[NDArray[np.float64]] = []
    current: list[tuple[float, float]] | None = None
    for n, i in enumerate(np.append(cuts, cuts[0] + len(lon) - 1)):  # from each cut to the next, round the ring
        j = i % (len(lon) - 1)
        edge = hi + width * min(k[j], k[j + 1])
        t = (edge - lon[j]) / (lon[j + 1] - lon[j])
        y = float(lat[j] + t * (lat[j + 1] - lat[j]))
        east = k[j + 1] > k[j]
        if current is not None:
            current.append((hi if east else lo, y))
            pieces.append(np.array(current))
        if n == len(cuts):
            break
        current = [(lo if east else hi, y)]
        stop = cuts[(n + 1) % len(cuts)] + (len(lon) - 1 if n + 1 == len(cuts) else 0)
        for m in range(j + 1, stop + 1):
            mm = m % (len(lon) - 1)
            current.append((x[mm], lat[mm]))
    return pieces


def _joined(arcs: list[NDArray[np.float64]]) -> tuple[tuple[tuple[NDArray[np.float64], ...], ...], bool, bool]:
    """Arcs that run from the window's edge to its edge, joined into rings along the edge counter-clockwise."""
    starts = np.array([_edge_position(*a[0]) for a in arcs])
    unused, north, south = set(range(len(arcs))), False, False
    polygons: list[tuple[NDArray[np.float64], ...]] = []
    while unused:
        first = current = min(unused)
        ring: list[tuple[float, ...]] = []
        while True:
            unused.discard(current)
            ring.extend(map(tuple, arcs[current]))
            s = _edge_position(*arcs[current][-1])
            ahead = (starts - s) % 4.0
            nxt = int(np.argmin(np.where(ahead > 0.0, ahead, 4.0)))
            end = s + ahead[nxt]
            for corner, xy in CORNERS + tuple((c + 4.0, xy) for c, xy in CORNERS):
                if s < corner < end:
                    ring.append(xy)
            north |= s < 2.5 < end or s < 6.5 < end
            south |= s < 4.5 < end
            if nxt == first:
                break
            current = nxt
        ring.append(ring[0])
        polygons.append((np.array(ring),))
    return tuple(polygons), north, south

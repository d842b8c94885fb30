"""World maps in the manner of AFWAL-TR-82-3036 Section IV (Figs. 31-33), with plain matplotlib and numpy.

Two projections, as in the report: cylindrical equidistant (x = longitude, y = latitude) and orthographic
(the globe seen from infinitely far away, centred on the footprint, the far hemisphere hidden). No
coastlines: nothing is loaded from outside the project, so the map is a graticule every 30 deg. On each map:
the footprint (its boundary densified along great circles, optionally shaded inside), the initial point as a
filled circle and the ground track of the initial great circle, dashed. On the cylindrical map a line that
would cross longitude 180 is cut there, each piece drawn to the map's edge (the report leaves such points
unconnected, Fig. 32); on the orthographic map lines stop at the limb.

Every function returns a matplotlib Figure built without pyplot's registry; write it with
footprint.pictures.figures.save (PNG or SVG by the suffix).
"""

import math
from dataclasses import dataclass

import numpy as np
from matplotlib.figure import Figure
from matplotlib.path import Path as PolygonPath

from footprint.core.sphere import (
    MEAN_RADIUS_NMI,
    Reference,
    downrange_crossrange_nmi,
    great_circle,
    latlon_of,
    unit_vectors,
    wrap_longitude,
)

GRATICULE_DEG = 30.0  # the graticule's spacing, meridians and parallels
SAMPLE_DEG = 0.5  # lines are densified along great circles to at most this arc between samples
SHADE_PIXELS = 500  # the shading raster's side, cylindrical (x2 in longitude) and orthographic
CIRCUMFERENCE_NMI = 2.0 * math.pi * MEAN_RADIUS_NMI
GRID_STYLE = {"color": "0.78", "lw": 0.6, "zorder": 1}
TRACK_STYLE = {"color": "0.35", "lw": 0.9, "ls": (0, (6, 4)), "zorder": 2}


@dataclass
class MapLayer:
    """One line on the map: a footprint's boundary (closed) or any path of points (lat, lon in deg)."""

    latitude_deg: np.ndarray
    longitude_deg: np.ndarray
    label: str = ""
    closed: bool = True
    color: str = "k"
    linestyle: object = "-"
    linewidth: float = 1.5
    marker: str | None = None  # drawn at the given points (not at the densified samples)
    reference: Reference | None = None  # the initial point (filled circle) and its great circle (dashed)
    shade: bool = False  # shade the inside: needs `reference`
    downrange_hint_nmi: np.ndarray | None = None  # the points' down-ranges, for footprints past 180 deg


def footprint_layer(
    latitude_deg, longitude_deg, reference: Reference | None = None, downrange_nmi=None, **style
) -> MapLayer:
    return MapLayer(
        np.asarray(latitude_deg, float),
        np.asarray(longitude_deg, float),
        reference=reference,
        downrange_hint_nmi=None if downrange_nmi is None else np.asarray(downrange_nmi, float),
        **style,
    )


# ----------------------------------------------------------------------- sampling (the sphere: core.sphere)
def densify(latitude_deg, longitude_deg, closed=False, sample_deg=SAMPLE_DEG):
    """Unit vectors along the great-circle arcs joining the points, no sample more than sample_deg apart."""
    v = unit_vectors(latitude_deg, longitude_deg)
    if closed and len(v) > 1:
        v = np.vstack([v, v[:1]])
    out = [v[:1]]
    for a, b in zip(v[:-1], v[1:]):
        ang = math.atan2(np.linalg.norm(np.cross(a, b)), float(a @ b))
        n = max(1, int(math.ceil(math.degrees(ang) / sample_deg)))
        t = np.linspace(0.0, 1.0, n + 1)[1:, None]
        if ang < 1e-12:
            out.append(np.repeat(b[None], n, axis=0))
            continue
        s = math.sin(ang)
        out.append((np.sin((1 - t) * ang) * a + np.sin(t * ang) * b) / s)  # slerp
    return np.vstack(out)


def arc_deg(start_deg=-180.0, stop_deg=180.0, sample_deg=SAMPLE_DEG) -> np.ndarray:
    """Angles from start_deg to stop_deg (both included) every sample_deg: where a great circle is sampled."""
    return np.arange(start_deg, stop_deg + 0.5 * sample_deg, sample_deg)


def footprint_center(latitude_deg, longitude_deg):
    """A view centre for a footprint: the direction of the mean of its densified boundary (lat, lon deg)."""
    v = densify(latitude_deg, longitude_deg, closed=True).mean(axis=0)
    if np.linalg.norm(v) < 1e-9:
        v = unit_vectors(latitude_deg[0], longitude_deg[0])
    lat, lon = latlon_of(v / np.linalg.norm(v))
    return float(lat), float(lon)


# ------------------------------------------------------------------------------------------- projections
class Cylindrical:
    """Cylindrical equidistant: x = longitude, y = latitude (deg). Lines are cut at longitude 180."""

    name = "cylindrical equidistant"

    def __init__(self, extent=(-180.0, 180.0, -90.0, 90.0)):
        self.extent = extent

    def lines(self, v):
        """(x, y) with NaN breaks; a segment crossing the date line ends at +-180 and goes on from -+180."""
        lat, lon = latlon_of(v)
        xs, ys = [lon[:1]], [lat[:1]]
        for i in range(1, len(lon)):
            a, b = lon[i - 1], lon[i]
            if abs(b - a) > 180.0:  # the short way round crosses the date line
                edge = 180.0 if a > 0 else -180.0
                b_unwrapped = b + 360.0 if a > 0 else b - 360.0
                f = (edge - a) / (b_unwrapped - a)
                lat_edge = lat[i - 1] + f * (lat[i] - lat[i - 1])
                xs.append(np.array([edge, np.nan, -edge]))
                ys.append(np.array([lat_edge, np.nan, lat_edge]))
            xs.append(lon[i : i + 1])
            ys.append(lat[i : i + 1])
        return np.concatenate(xs), np.concatenate(ys)

    def points(self, lat_deg, lon_deg):
        return np.asarray(lon_deg, float), np.asarray(lat_deg, float)

    def visible(self, lat_deg, lon_deg):
        return np.ones(np.shape(lat_deg), bool)

    def raster(self, n=SHADE_PIXELS):
        """Pixel centres as unit vectors (rows: latitude up) and the image extent."""
        lon = np.linspace(-180.0, 180.0, 2 * n, endpoint=False) + 180.0 / (2 * n)
        lat = np.linspace(-90.0, 90.0, n, endpoint=False) + 90.0 / n
        LON, LAT = np.meshgrid(lon, lat)
        return unit_vectors(LAT, LON), np.ones(LAT.shape, bool), (-180.0, 180.0, -90.0, 90.0)

    def setup(self, ax):
        x0, x1, y0, y1 = self.extent
        for lon in np.arange(-180.0, 180.0 + 1e-9, GRATICULE_DEG):
            ax.plot([lon, lon], [-90, 90], **GRID_STYLE)
        for lat in np.arange(-90.0, 90.0 + 1e-9, GRATICULE_DEG):
            ax.plot([-180, 180], [lat, lat], **GRID_STYLE)
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ticks = np.arange(-180.0, 180.0 + 1e-9, GRATICULE_DEG)
        ax.set_xticks([t for t in ticks if x0 <= t <= x1])
        ax.set_yticks([t for t in np.arange(-90.0, 90.0 + 1e-9, GRATICULE_DEG) if y0 <= t <= y1])
        ax.set_xticklabels([_lon_label(t) for t in ax.get_xticks()], fontsize="small")
        ax.set_yticklabels([_lat_label(t) for t in ax.get_yticks()], fontsize="small")
        for s in ax.spines.values():
            s.set_linewidth(0.8)


class Orthographic:
    """The globe from infinitely far above (lat0, lon0): x = v . east, y = v . north; the far hemisphere
    (v . centre < 0) is hidden."""

    name = "orthographic"

    def __init__(self, center_latitude_deg, center_longitude_deg):
        self.center = (float(center_latitude_deg), float(center_longitude_deg))
        lat, lon = np.radians(self.center)
        self.c = np.array([math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat)])
        self.e = np.array([-math.sin(lon), math.cos(lon), 0.0])
        self.n = np.cross(self.c, self.e)

    def lines(self, v):
        """(x, y) of the visible parts, NaN between them; each part ends on the limb."""
        d = v @ self.c
        xs, ys = [], []
        vis_prev = None
        for i in range(len(v)):
            vis = d[i] >= 0.0
            if vis_prev is not None and vis != vis_prev:  # crosses the limb: end (or start) the part on it
                f = d[i - 1] / (d[i - 1] - d[i])
                w = v[i - 1] + f * (v[i] - v[i - 1])
                w = w - (w @ self.c) * self.c
                w = w / np.linalg.norm(w)
                xs.append(w @ self.e)
                ys.append(w @ self.n)
                if not vis:
                    xs.append(np.nan)
                    ys.append(np.nan)
            if vis:
                xs.append(v[i] @ self.e)
                ys.append(v[i] @ self.n)
            vis_prev = vis
        return np.array(xs, float), np.array(ys, float)

    def points(self, lat_deg, lon_deg):
        v = unit_vectors(lat_deg, lon_deg)
        return v @ self.e, v @ self.n

    def visible(self, lat_deg, lon_deg):
        return unit_vectors(lat_deg, lon_deg) @ self.c >= 0.0

    def raster(self, n=SHADE_PIXELS):
        s = np.linspace(-1.0, 1.0, n, endpoint=False) + 1.0 / n
        X, Y = np.meshgrid(s, s)
        on_globe = X**2 + Y**2 <= 1.0
        Z = np.sqrt(np.clip(1.0 - X**2 - Y**2, 0.0, None))
        v = X[..., None] * self.e + Y[..., None] * self.n + Z[..., None] * self.c
        return v, on_globe, (-1.0, 1.0, -1.0, 1.0)

    def setup(self, ax):
        t = np.linspace(0.0, 2.0 * math.pi, 721)
        ax.fill(np.cos(t), np.sin(t), color="white", zorder=0)
        for lon in np.arange(-180.0, 180.0, GRATICULE_DEG):
            ax.plot(*self.lines(unit_vectors(np.arange(-90.0, 90.0 + 1e-9, SAMPLE_DEG), lon)), **GRID_STYLE)
        for lat in np.arange(-60.0, 60.0 + 1e-9, GRATICULE_DEG):
            ax.plot(*self.lines(unit_vectors(lat, np.arange(-180.0, 180.0 + 1e-9, SAMPLE_DEG))), **GRID_STYLE)
        ax.plot(np.cos(t), np.sin(t), color="k", lw=1.0, zorder=4)  # the limb
        ax.set_xlim(-1.04, 1.04)
        ax.set_ylim(-1.04, 1.04)
        ax.set_aspect("equal")
        ax.set_axis_off()
        ax.text(
            0.0,
            -1.1,
            f"centre {_lat_label(self.center[0])}, {_lon_label(self.center[1])}",
            ha="center",
            va="top",
            fontsize="small",
        )


def _lon_label(x):
    x = float(wrap_longitude(float(x), closed_above=True))
    return f"{abs(x):.0f}°" + ("" if x in (0.0, 180.0) else ("E" if x > 0 else "W"))


def _lat_label(y):
    y = float(y)
    return f"{abs(y):.0f}°" + ("" if y == 0 else ("N" if y > 0 else "S"))


# ----------------------------------------------------------------------------------------------- drawing
def draw_map(ax, projection, layers: list[MapLayer], title=None, legend="lower left"):
    """Graticule, then each layer: shading, boundary, markers, initial point and ground track."""
    projection.setup(ax)
    refs = []
    for layer in layers:
        if layer.shade and layer.reference is not None:
            _shade(ax, projection, layer)
        v = densify(layer.latitude_deg, layer.longitude_deg, closed=layer.closed)
        x, y = projection.lines(v)
        ax.plot(
            x,
            y,
            color=layer.color,
            ls=layer.linestyle,
            lw=layer.linewidth,
            zorder=5,
            label=layer.label or None,
            gid="footprint",
        )
        if layer.marker:
            keep = projection.visible(layer.latitude_deg, layer.longitude_deg)
            px, py = projection.points(layer.latitude_deg[keep], layer.longitude_deg[keep])
            ax.plot(px, py, ls="none", marker=layer.marker, ms=3.0, color=layer.color, zorder=6)
        if layer.reference is not None and layer.reference not in refs:
            refs.append(layer.reference)
    for ref in refs:
        ax.plot(*projection.lines(great_circle(ref, arc_deg())), **TRACK_STYLE, gid="ground_track")
        _direction_arrow(ax, projection, ref)
        if projection.visible(ref.latitude_deg, ref.longitude_deg):
            px, py = projection.points(ref.latitude_deg, ref.longitude_deg)
            ax.plot(px, py, "o", color="k", ms=6.5, zorder=7, gid="initial_point")
    if title:
        ax.set_title(title, fontsize="medium")
    if legend and any(layer.label for layer in layers):
        ax.legend(fontsize="x-small", loc=legend, framealpha=0.9)
    return ax


def _direction_arrow(ax, projection, ref):
    """An arrowhead on the ground track a few degrees past the initial point: the way the entry heads."""
    v = great_circle(ref, arc_deg(6.0, 10.0, 2.0))
    if np.all(projection.visible(*latlon_of(v))):
        lat, lon = latlon_of(v)
        (x0, x1), (y0, y1) = projection.points(lat[[0, -1]], lon[[0, -1]])
        if abs(x1 - x0) < 90.0:  # not across the date line
            ax.annotate(
                "",
                xy=(x1, y1),
                xytext=(x0, y0),
                zorder=7,
                arrowprops={"arrowstyle": "-|>", "color": "k", "lw": 1.0, "mutation_scale": 11},
            )


def _shade(ax, projection, layer: MapLayer):
    """Grey where the footprint is: pixels whose (down-range, cross-range) about the initial point fall
    inside the boundary's polygon in that plane (robust over the date line, the poles and past 180 deg)."""
    ref = layer.reference
    v, keep, extent = projection.raster()
    lat, lon = latlon_of(v)
    d, c = downrange_crossrange_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    bd, bc = _boundary_ranges(layer)
    poly = PolygonPath(np.column_stack([bd, bc]))
    inside = np.zeros(d.shape, bool)
    for turn in (-1, 0, 1):  # a footprint longer than half the circumference wraps
        pts = np.column_stack([(d + turn * CIRCUMFERENCE_NMI).ravel(), c.ravel()])
        inside |= poly.contains_points(pts).reshape(d.shape)
    inside &= keep
    rgba = np.zeros(inside.shape + (4,))
    rgba[inside] = (0.55, 0.55, 0.55, 0.35)
    ax.imshow(rgba, extent=extent, origin="lower", interpolation="nearest", zorder=3, gid="shade")


def _boundary_ranges(layer: MapLayer):
    """The closed boundary in (down-range, cross-range) about the layer's reference, densified, the
    down-range continued along the boundary from the first point (placed at its hint)."""
    ref = layer.reference
    v = densify(layer.latitude_deg, layer.longitude_deg, closed=True)
    lat, lon = latlon_of(v)
    d, c = downrange_crossrange_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    ang = np.unwrap(d / MEAN_RADIUS_NMI)  # downrange_crossrange_nmi(unwrap=True) but for the rounding of d / R'
    d = ang * MEAN_RADIUS_NMI
    if layer.downrange_hint_nmi is not None:
        d += CIRCUMFERENCE_NMI * round((layer.downrange_hint_nmi[0] - d[0]) / CIRCUMFERENCE_NMI)
    return d, c


def auto_extent(layers: list[MapLayer], margin_deg=10.0, step_deg=10.0):
    """The smallest box (multiples of step_deg, plus a margin) that holds the layers on the cylindrical
    map; the whole world when a layer crosses the date line."""
    xs, ys = [], []
    cyl = Cylindrical()
    for layer in layers:
        x, y = cyl.lines(densify(layer.latitude_deg, layer.longitude_deg, closed=layer.closed))
        if np.isnan(x).any():
            return -180.0, 180.0, -90.0, 90.0
        xs.append(x)
        ys.append(y)
        if layer.reference is not None:  # the initial point stays in view
            xs.append(np.array([layer.reference.longitude_deg]))
            ys.append(np.array([layer.reference.latitude_deg]))
    x, y = np.concatenate(xs), np.concatenate(ys)
    lo = lambda a: step_deg * math.floor((a - margin_deg) / step_deg)  # noqa: E731
    hi = lambda a: step_deg * math.ceil((a + margin_deg) / step_deg)  # noqa: E731
    return max(-180.0, lo(x.min())), min(180.0, hi(x.max())), max(-90.0, lo(y.min())), min(90.0, hi(y.max()))


# ------------------------------------------------------------------------------------------------ figures
def map_figure(layers: list[MapLayer], projection="cylindrical", center=None, extent=None, title=None) -> Figure:
    """One map. projection: "cylindrical" (extent (lon0, lon1, lat0, lat1), "auto", or the world) or
    "orthographic" (centre (lat, lon) in deg; default: the first layer's footprint centre)."""
    return panels_figure(
        [{"projection": projection, "layers": layers, "center": center, "extent": extent, "title": title}], ncols=1
    )


def panels_figure(panels: list[dict], ncols=1, title=None, panel_size=(7.0, 3.8)) -> Figure:
    """Several maps in a grid, like the report's Figs. 31 and 32: each panel a dict with projection,
    layers, and optionally center, extent, title, legend (a matplotlib location, or False)."""
    nrows = math.ceil(len(panels) / ncols)
    ortho = all(p["projection"] == "orthographic" for p in panels)
    w, h = (4.6, 4.6) if ortho else panel_size
    fig = Figure(figsize=(w * ncols, h * nrows + (0.4 if title else 0.0)), layout="constrained")
    axes = np.atleast_1d(fig.subplots(nrows, ncols, squeeze=False)).ravel()
    for ax, panel in zip(axes, panels):
        draw_map(
            ax,
            make_projection(panel),
            panel["layers"],
            title=panel.get("title"),
            legend=panel.get("legend", "lower left"),
        )
    for ax in axes[len(panels) :]:
        ax.set_axis_off()
    if title:
        fig.suptitle(title)
    return fig


def make_projection(panel: dict):
    layers = panel["layers"]
    if panel["projection"] == "orthographic":
        center = panel.get("center") or footprint_center(layers[0].latitude_deg, layers[0].longitude_deg)
        return Orthographic(*center)
    if panel["projection"] != "cylindrical":
        raise ValueError(f"projection {panel['projection']!r}: 'cylindrical' or 'orthographic'")
    extent = panel.get("extent")
    if extent == "auto":
        extent = auto_extent(layers)
    return Cylindrical(extent or (-180.0, 180.0, -90.0, 90.0))

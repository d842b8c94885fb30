"""Which landing sites a footprint reaches, from which parts of which revolutions (AFWAL-TR-82-3036 Section IV,
questions 1-3: the coverage from a deorbit point, the effect of the node's motion, the portions of orbits
that allow landing at designated sites).

A footprint is a closed polygon of points given in down-range and cross-range (nmi) about its own
reference, the entry point, with each point's flight time from entry (as FootprintPoint has them). It is
placed at every deorbit point of a grid in argument of latitude u over a span of revolutions: its
reference goes to the point under the orbit and its initial great circle along the orbit plane
(orbits.frames). For each placement the sites are carried into the placement's (down-range, cross-range)
chart, where the footprint's edges are straight (the convention of footprints.area_nmi2), and tested with
the even-odd rule. Nothing uses raw longitude differences, so the +-180 meridian and the poles need no care.

- Down-range past half a circumference (the L/D 1.89 footprint reaches 14,869 nmi > pi R' = 10,807 nmi):
  a site at chart down-range d is also at d + 2 pi R' k; every branch k that can meet the polygon is tested.
- Earth rotation "approximate" (Section IV.3): each footprint point moves west by omega_p t (its flight
  time), latitude unchanged, theta_rot = theta - omega_p t; the shifted vertices are carried back into
  the chart (down-range unwrapped next to the unshifted one) and joined by straight edges there. The
  reference (t = 0) does not move, which is why the footprint's reference must be its entry point.
- Margin: signed distance (nmi, positive inside) from the site to the polygon boundary in the chart,
  with the down-range axis scaled by cos(cross-range / R') at the site (the chart's metric there), so
  that near the boundary it is the distance on the sphere to first order. Far outside (thousands of nmi)
  it is a chart distance, not a great-circle one.

The work is vectorized over placements x sites x edges in chunks of placements; `margins_reference` is a
plain-Python loop over the same geometry, kept as an independent check and as the benchmark's baseline.
"""

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core.errors import Stopped
from footprint.core.orbits import CircularOrbit, frames, time_s
from footprint.core.sphere import MEAN_RADIUS_NMI, Reference, great_circle_frame, unit_vectors

EARTH_ROTATION = ("none", "approximate")
ON_BOUNDARY_NMI = 1e-6  # a site this close to an edge counts as inside (as footprints._inside does)
CHUNK_ELEMENTS = 100_000  # placements x sites x edges per chunk: 0.8 MB per temporary, stays in cache (4x 400k)


@dataclass(frozen=True)
class Window:
    """A contiguous run of deorbit arguments of latitude, within one revolution, that reach one site.

    u_start_deg and u_end_deg are the first and last grid values inside (the true edges lie within one
    step outside them); times are the deorbit times of those two grid points, seconds since the epoch."""

    site: int
    revolution: int
    u_start_deg: float
    u_end_deg: float
    samples: int
    max_margin_nmi: float
    deorbit_time_start_s: float
    deorbit_time_end_s: float

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass
class Reach:
    revolutions: NDArray[np.int_]  # (R,)
    u_deg: NDArray[np.float64]  # (U,) deorbit arguments of latitude
    deorbit_time_s: NDArray[np.float64]  # (R, U)
    margin_nmi: NDArray[np.float64]  # (R, U, S); NaN where a placement lies past the time span
    inside: NDArray[np.bool_]  # (R, U, S)
    windows: list[Window] = field(default_factory=list)

    def passes(self, site: int) -> list[list[Window]]:
        """The site's windows grouped into passes: a window that runs to the end of a revolution and one
        that starts the next at u = 0 are one opportunity (the grid splits it at the node)."""
        out: list[list[Window]] = []
        last = len(self.u_deg) - 1
        for w in (w for w in self.windows if w.site == site):
            prev = out[-1][-1] if out else None
            if (
                prev is not None
                and prev.revolution + 1 == w.revolution
                and prev.u_end_deg == self.u_deg[last]
                and w.u_start_deg == self.u_deg[0]
            ):
                out[-1].append(w)
            else:
                out.append([w])
        return out


# ------------------------------------------------------------------------------------------ the kernel
def _wrap_pi(a: NDArray[np.float64]) -> NDArray[np.float64]:
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def branches(dmin: float, dmax: float) -> range:
    """Integers k for which a chart down-range in (-pi, pi] shifted by 2 pi k can meet [dmin, dmax] (radians)."""
    lo = math.ceil((dmin - math.pi) / (2.0 * math.pi) - 1e-12)
    hi = math.floor((dmax + math.pi) / (2.0 * math.pi) + 1e-12)
    return range(lo, hi + 1)


def vertices_in_chart(
    p0: NDArray[np.float64],
    d0: NDArray[np.float64],
    n: NDArray[np.float64],
    down_rad: NDArray[np.float64],
    cross_rad: NDArray[np.float64],
    shift_rad: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The footprint's vertices (G, P) in each placement's chart after the rotation shift (radians).

    p0, d0, n: (G, 3) placement frames; down_rad, cross_rad, shift_rad: (P,), shift positive west."""
    cc = np.cos(cross_rad)
    v = (
        (cc * np.cos(down_rad))[None, :, None] * p0[:, None, :]
        + (cc * np.sin(down_rad))[None, :, None] * d0[:, None, :]
        + np.sin(cross_rad)[None, :, None] * n[:, None, :]
    )  # placed points (G, P, 3)
    cphi, sphi = np.cos(shift_rad), np.sin(shift_rad)  # turn about the polar axis by -shift (west)
    x = v[..., 0] * cphi + v[..., 1] * sphi
    y = -v[..., 0] * sphi + v[..., 1] * cphi
    vs = np.stack([x, y, v[..., 2]], axis=-1)
    dv = np.arctan2(np.einsum("gpk,gk->gp", vs, d0), np.einsum("gpk,gk->gp", vs, p0))
    dv = down_rad[None, :] + _wrap_pi(dv - down_rad[None, :])  # the branch next to the unshifted point
    cv = np.arcsin(np.clip(np.einsum("gpk,gk->gp", vs, n), -1.0, 1.0))
    return dv, cv


def margins(
    p0: NDArray[np.float64],
    d0: NDArray[np.float64],
    n: NDArray[np.float64],
    down_nmi: ArrayLike,
    cross_nmi: ArrayLike,
    flight_time_s: ArrayLike,
    sites_unit: NDArray[np.float64],
    shift_deg_s: float = 0.0,
    radius_nmi: float = MEAN_RADIUS_NMI,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Signed margins (G, S) in nmi, positive inside, and inside flags, for G placements and S sites.

    p0, d0, n: (G, 3) earth-fixed frames of the placements (reference point, initial direction, left
    pole); down_nmi, cross_nmi, flight_time_s: (P,) the closed footprint polygon about its reference;
    sites_unit: (S, 3); shift_deg_s: the earth's rotation rate for the Section IV.3 shift (0: none)."""
    d = np.asarray(down_nmi, float) / radius_nmi
    c = np.asarray(cross_nmi, float) / radius_nmi
    if shift_deg_s:
        dv, cv = vertices_in_chart(p0, d0, n, d, c, np.radians(shift_deg_s * np.asarray(flight_time_s, float)))
    else:
        dv, cv = d[None, :], c[None, :]
    dv = np.concatenate([dv, dv[:, :1]], axis=1)  # closed: edge j runs from vertex j to vertex j + 1
    cv = np.concatenate([cv, cv[:, :1]], axis=1)
    ds = np.arctan2(d0 @ sites_unit.T, p0 @ sites_unit.T)  # (G, S) the sites in each chart
    cs = np.arcsin(np.clip(n @ sites_unit.T, -1.0, 1.0))
    scale = np.cos(cs)[:, :, None]  # the chart's metric at the site: d(down) shrinks by cos(cross)
    # the polygon about the site, branch k = 0: x along down-range (scaled), y along cross-range, (G, S, P + 1)
    xx = (dv[:, None, :] - ds[:, :, None]) * scale
    yy = cv[:, None, :] - cs[:, :, None]
    x, y, ex, ey = xx[..., :-1], yy[..., :-1], np.diff(xx, axis=-1), np.diff(yy, axis=-1)
    straddles = (y > 0.0) != (yy[..., 1:] > 0.0)
    xi = x - y * ex / np.where(straddles, ey, 1.0)  # where an edge crosses the ray y = 0 from the site
    len2 = ex * ex + ey * ey
    inv_len2 = 1.0 / np.where(len2 > 0.0, len2, 1.0)
    along = -(x * ex + y * ey)  # projection of the site on each edge, times its length
    best = np.full(ds.shape, -np.inf)
    inside = np.zeros(ds.shape, bool)
    eps = ON_BOUNDARY_NMI / radius_nmi
    for k in branches(float(dv.min()), float(dv.max())):
        off = 2.0 * np.pi * k * scale  # the site at down-range ds + 2 pi k: the polygon moves back by it
        odd = (np.count_nonzero(straddles & (xi > off), axis=-1) & 1).astype(bool)  # even-odd, ray to +x
        t = np.clip((along + off * ex) * inv_len2, 0.0, 1.0)
        dx, dy = x - off + t * ex, y + t * ey
        dist = np.sqrt(np.min(dx * dx + dy * dy, axis=-1))
        hit = odd | (dist <= eps)
        inside |= hit
        np.maximum(best, np.where(hit, dist, -dist), out=best)
    return best * radius_nmi, inside


def placement_margins(
    reference: Reference,
    down_nmi: ArrayLike,
    cross_nmi: ArrayLike,
    flight_time_s: ArrayLike,
    sites_latitude_deg: ArrayLike,
    sites_longitude_deg: ArrayLike,
    shift_deg_s: float = 0.0,
    radius_nmi: float = MEAN_RADIUS_NMI,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """One placement: the footprint about `reference` (its entry point); margins (S,) nmi and inside (S,)."""
    p0, d0, n = great_circle_frame(reference.latitude_deg, reference.longitude_deg, reference.heading_deg)
    sites = unit_vectors(
        np.atleast_1d(np.asarray(sites_latitude_deg, float)), np.atleast_1d(np.asarray(sites_longitude_deg, float))
    )
    m, inside = margins(p0[None], d0[None], n[None], down_nmi, cross_nmi, flight_time_s, sites, shift_deg_s, radius_nmi)
    return m[0], inside[0]


# ---------------------------------------------------------------------------------------- the analysis
def reach(
    footprint_down_nmi: ArrayLike,
    footprint_cross_nmi: ArrayLike,
    flight_time_s: ArrayLike,
    sites_lat: ArrayLike,
    sites_lon: ArrayLike,
    orbit: CircularOrbit,
    revolutions: ArrayLike,
    u_step_deg: float = 1.0,
    earth_rotation: str = "approximate",
    entry_offset_nmi: float = 0.0,
    time_span_s: float | None = None,
    radius_nmi: float = MEAN_RADIUS_NMI,
    chunk_elements: int = CHUNK_ELEMENTS,
    on_progress: Callable[[float, str], bool | None] | None = None,
) -> Reach:
    """Place the footprint at every deorbit point (revolution, u on a grid of u_step_deg from the node) and
    decide which sites it covers.

    footprint_*: (P,) the closed polygon about its entry point (down-range and cross-range in nmi, flight
    time in s); sites_lat, sites_lon: (S,) deg; revolutions: the revolution numbers (1 starts at the
    epoch); earth_rotation: "none" or "approximate" (Section IV.3, with the orbit's rotation rate);
    entry_offset_nmi: the arc of the orbit from deorbit to entry; time_span_s: placements whose deorbit
    time lies past it are left out (NaN margins, never inside). on_progress(fraction, note) before each chunk of
    placements (True stops: errors.Stopped)."""
    if earth_rotation not in EARTH_ROTATION:
        raise ValueError(f"earth_rotation must be one of {EARTH_ROTATION}, not {earth_rotation!r}")
    revs = np.asarray(revolutions, int).ravel()
    u = np.arange(0.0, 360.0 - 1e-9, u_step_deg)
    rev_g, u_g = np.meshgrid(revs, u, indexing="ij")  # (R, U)
    p0, d0, n, _ = frames(orbit, rev_g.ravel(), u_g.ravel(), entry_offset_nmi, radius_nmi)
    t_deorbit = time_s(orbit, rev_g, u_g)
    sites = unit_vectors(np.atleast_1d(np.asarray(sites_lat, float)), np.atleast_1d(np.asarray(sites_lon, float)))
    shift = orbit.rotation_rate_deg_s if earth_rotation == "approximate" else 0.0
    down = np.asarray(footprint_down_nmi, float)
    g_total, s_total = p0.shape[0], sites.shape[0]
    step = max(1, chunk_elements // max(1, s_total * down.size))
    margin: NDArray[np.float64] = np.empty((g_total, s_total))
    inside: NDArray[np.bool_] = np.empty((g_total, s_total), bool)
    for a in range(0, g_total, step):
        if on_progress is not None and on_progress(a / g_total, f"placement {a:,} of {g_total:,}"):
            raise Stopped(f"stopped at placement {a:,} of {g_total:,}")
        b = min(g_total, a + step)
        margin[a:b], inside[a:b] = margins(
            p0[a:b], d0[a:b], n[a:b], down, footprint_cross_nmi, flight_time_s, sites, shift, radius_nmi
        )
    margin = margin.reshape(len(revs), len(u), s_total)
    inside = inside.reshape(len(revs), len(u), s_total)
    if time_span_s is not None:
        late = t_deorbit > time_span_s + 1e-9
        margin[late] = np.nan
        inside[late] = False
    return Reach(
        revolutions=revs,
        u_deg=u,
        deorbit_time_s=t_deorbit,
        margin_nmi=margin,
        inside=inside,
        windows=windows(revs, u, t_deorbit, margin, inside),
    )


def windows(
    revs: NDArray[np.int_],
    u: NDArray[np.float64],
    t_deorbit: NDArray[np.float64],
    margin: NDArray[np.float64],
    inside: NDArray[np.bool_],
) -> list[Window]:
    """Contiguous runs of inside along u, per revolution and site, ordered by site, then revolution, then u."""
    r_n, u_n, s_n = inside.shape
    flags = np.zeros((r_n, s_n, u_n + 2), bool)
    flags[:, :, 1:-1] = np.transpose(inside, (0, 2, 1))
    edges = np.diff(flags.astype(np.int8), axis=-1)  # +1 where a run starts, -1 one past where it ends
    rs, ss, starts = np.nonzero(edges == 1)
    _, _, stops = np.nonzero(edges == -1)  # same (r, s) order, one stop per start
    if len(starts) == 0:
        return []
    m = np.full((r_n, s_n, u_n + 1), -np.inf)
    m[:, :, :-1] = np.transpose(np.nan_to_num(margin, nan=-np.inf), (0, 2, 1))
    flat = m.ravel()
    base = (rs * s_n + ss) * (u_n + 1)
    idx = np.empty(2 * len(starts), np.int64)
    idx[0::2], idx[1::2] = base + starts, base + stops
    best = np.maximum.reduceat(flat, idx)[0::2]
    order = np.lexsort((starts, rs, ss))
    return [
        Window(
            site=int(ss[i]),
            revolution=int(revs[rs[i]]),
            u_start_deg=float(u[starts[i]]),
            u_end_deg=float(u[stops[i] - 1]),
            samples=int(stops[i] - starts[i]),
            max_margin_nmi=float(best[i]),
            deorbit_time_start_s=float(t_deorbit[rs[i], starts[i]]),
            deorbit_time_end_s=float(t_deorbit[rs[i], stops[i] - 1]),
        )
        for i in order
    ]


# --------------------------------------------------------------------------- a plain-Python reference
def margins_reference(
    frames_list: Iterable[tuple[Sequence[float], Sequence[float], Sequence[float]]],
    down_nmi: Iterable[float],
    cross_nmi: Iterable[float],
    flight_time_s: Iterable[float],
    sites_latlon_deg: Iterable[tuple[float, float]],
    shift_deg_s: float = 0.0,
    radius_nmi: float = MEAN_RADIUS_NMI,
) -> list[list[tuple[float, bool]]]:
    """The same margins by a plain Python loop over placements, sites, branches and edges (math only).

    frames_list: [(p0, d0, n)] 3-sequences; sites_latlon_deg: [(lat, lon)]. Returns a list of rows of
    (margin_nmi, inside). The independent check of `margins` and the benchmark's baseline."""
    two_pi = 2.0 * math.pi
    sites: list[tuple[float, float, float]] = []
    for lat, lon in sites_latlon_deg:
        la, lo = math.radians(lat), math.radians(lon)
        sites.append((math.cos(la) * math.cos(lo), math.cos(la) * math.sin(lo), math.sin(la)))
    poly = [
        (d / radius_nmi, c / radius_nmi, math.radians(shift_deg_s * t))
        for d, c, t in zip(down_nmi, cross_nmi, flight_time_s)
    ]
    eps = ON_BOUNDARY_NMI / radius_nmi
    rows: list[list[tuple[float, bool]]] = []
    for p0, d0, n in frames_list:
        verts: list[tuple[float, float]] = []
        for d, c, phi in poly:
            cc = math.cos(c)
            v: Sequence[float] = [
                cc * math.cos(d) * p0[k] + cc * math.sin(d) * d0[k] + math.sin(c) * n[k] for k in range(3)
            ]
            x = v[0] * math.cos(phi) + v[1] * math.sin(phi)  # theta_rot = theta - omega_p t
            y = -v[0] * math.sin(phi) + v[1] * math.cos(phi)
            v = (x, y, v[2])
            dd = math.atan2(sum(v[k] * d0[k] for k in range(3)), sum(v[k] * p0[k] for k in range(3)))
            dd = d + ((dd - d + math.pi) % two_pi - math.pi)
            verts.append((dd, math.asin(max(-1.0, min(1.0, sum(v[k] * n[k] for k in range(3)))))))
        dmin, dmax = min(v[0] for v in verts), max(v[0] for v in verts)
        row: list[tuple[float, bool]] = []
        for s in sites:
            ds = math.atan2(sum(s[k] * d0[k] for k in range(3)), sum(s[k] * p0[k] for k in range(3)))
            cs = math.asin(max(-1.0, min(1.0, sum(s[k] * n[k] for k in range(3)))))
            scale = math.cos(cs)
            best, hit_any = -math.inf, False
            for k in branches(dmin, dmax):
                pts = [((dv - ds - two_pi * k) * scale, cv - cs) for dv, cv in verts]
                odd, dist2 = False, math.inf
                for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1]):
                    if (y0 > 0.0) != (y1 > 0.0) and x0 - y0 * (x1 - x0) / (y1 - y0) > 0.0:
                        odd = not odd
                    ex, ey = x1 - x0, y1 - y0
                    len2 = ex * ex + ey * ey
                    t = 0.0 if len2 == 0.0 else max(0.0, min(1.0, -(x0 * ex + y0 * ey) / len2))
                    dist2 = min(dist2, (x0 + t * ex) ** 2 + (y0 + t * ey) ** 2)
                dist = math.sqrt(dist2)
                hit = odd or dist <= eps
                hit_any |= hit
                best = max(best, dist if hit else -dist)
            row.append((best * radius_nmi, hit_any))
        rows.append(row)
    return rows

"""Figures in the manner of AFWAL-TR-82-3036: footprints, parametric sets, iso-velocity contours, histories.

Every function returns a matplotlib Figure (built without pyplot's registry, so a service can make them
from any thread); `save` writes PNG or SVG by the file's suffix. Ranges are in nautical miles, altitudes
in thousands of feet, velocities in ft/s, angles in degrees, as in the report's plots.
"""

from itertools import cycle
from pathlib import Path
from textwrap import fill

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.ticker import StrMethodFormatter  # noqa: E402

from footprint.core.footprints import Footprint, FootprintPoint  # noqa: E402
from footprint.core.setting import ControlSetting  # noqa: E402
from footprint.core.trajectory import Trajectory  # noqa: E402

DOWNRANGE_LABEL = "Down-range (n.mi.)"
CROSSRANGE_LABEL = "Cross-range (n.mi.)"
PNG_DPI = 150
LABEL_OFFSET_PT = 7.0  # how far a point's label sits from its marker
SITE_MARGIN = 0.05  # a dispersion figure draws the sites within this fraction of the landings' extent
# line style and marker pairs that stay distinct when printed in black and white
LINE_STYLES = [
    ("-", "o"),
    ("--", "s"),
    ("-.", "^"),
    (":", "D"),
    ((0, (8, 3)), "v"),
    ((0, (5, 2, 1, 2, 1, 2)), "x"),
    ((0, (1, 1)), "P"),
    ((0, (10, 2, 2, 2)), "*"),
]


# ------------------------------------------------------------------------------------------ footprints
def footprint_figure(fp: Footprint, title=None, label_points=True, ax=None) -> Figure:
    """One footprint: the closed boundary, flown points filled, reflected points hollow, flown points that
    fell inside the boundary (a zero-lift point short of the steepest banks) as crosses (Figs. 12, 21)."""
    fig, ax = _axes(ax)
    ax.axhline(0.0, color="0.85", lw=0.8, zorder=0)  # the initial great circle
    d, c = _closed(fp.points)
    ax.plot(d, c, "k-", lw=1.4, gid="boundary", label=fp.method.replace("_", " "))
    flown = [p for p in fp.points if not p.mirrored]
    mirrored = [p for p in fp.points if p.mirrored]
    ax.plot(*_xy(flown), "ko", ms=4.5, ls="none", gid="flown")
    ax.plot(*_xy(mirrored), "o", mec="k", mfc="none", ms=4.5, ls="none", gid="mirrored")
    ax.plot(*_xy(_interior(fp)), "kx", ms=5, ls="none", gid="interior")
    if label_points:
        _label_points(ax, fp)
    _caption(ax, fp)
    _range_axes(ax, title)
    return fig


def save_footprint_plot(fp: Footprint, path, title=None) -> Path:
    return save(footprint_figure(fp, title=title), path)


def footprints_figure(footprints: dict[str, Footprint], title=None, ax=None) -> Figure:
    """Several footprints overlaid: families over entry angle or velocity (Fig. 15, App. C), comparisons
    of controls (Figs. 13, 14)."""
    fig, ax = _axes(ax)
    ax.axhline(0.0, color="0.85", lw=0.8, zorder=0)
    for (name, fp), (ls, marker) in zip(footprints.items(), cycle(LINE_STYLES)):
        ax.plot(*_closed(fp.points), ls=ls, marker=marker, ms=3.5, lw=1.2, label=name, gid="footprint")
    ax.legend(fontsize="small")
    _range_axes(ax, title)
    return fig


def dispersion_figure(result, title=None, ax=None) -> Figure:
    """A dispersed footprint (core.monte_carlo.DispersedFootprint): the nominal boundary, each setting's landing
    cloud and its 3-sigma ellipse, the footprints reached with probability >= p, the sites with their probability.
    Sites beyond the landings (SITE_MARGIN of their extent) are named in a caption, not drawn: they would stretch
    the axes."""
    fig, ax = _axes(ax, figsize=(9.0, 6.5))
    ax.axhline(0.0, color="0.85", lw=0.8, zorder=0)
    b = result.nominal_boundary
    ax.plot(
        b["downrange_nmi"] + b["downrange_nmi"][:1],
        b["crossrange_nmi"] + b["crossrange_nmi"][:1],
        "k-",
        lw=1.2,
        label="nominal footprint",
        gid="nominal",
    )
    down, cross = result.clouds["downrange_nmi"], result.clouds["crossrange_nmi"]
    ax.plot(
        down.ravel(),
        cross.ravel(),
        ".",
        color="0.55",
        ms=1.0,
        alpha=0.5,
        ls="none",
        gid="clouds",
        label=f"landings of {result.samples:,} samples",
        rasterized=True,
    )
    for i, f in enumerate(result.flights):
        if "3" in f.get("ellipses", {}):
            e = f["ellipses"]["3"]
            ax.plot(
                e["downrange_nmi"],
                e["crossrange_nmi"],
                "-",
                color="tab:blue",
                lw=0.9,
                gid="ellipse",
                label=r"3$\sigma$ ellipses" if i == 0 else None,
            )
    for c, ls, color in zip(result.confidence, cycle(["--", "-.", ":"]), cycle(["tab:orange", "tab:red", "purple"])):
        for j, ring in enumerate(c["rings"]):  # above the nominal boundary, which the p = 0.5 ring lies near
            ax.plot(
                ring["downrange_nmi"],
                ring["crossrange_nmi"],
                ls=ls,
                color=color,
                lw=1.5,
                gid="confidence",
                zorder=3,
                label=f"reached with probability $\\geq$ {c['level']:g}" if j == 0 else None,
            )
    x = np.concatenate([np.ravel(down), b["downrange_nmi"]])
    y = np.concatenate([np.ravel(cross), b["crossrange_nmi"]])
    x_lo, x_hi, y_lo, y_hi = np.nanmin(x), np.nanmax(x), np.nanmin(y), np.nanmax(y)
    mx, my = SITE_MARGIN * (x_hi - x_lo), SITE_MARGIN * (y_hi - y_lo)
    x_mid, y_mid = 0.5 * (x_lo + x_hi), 0.5 * (y_lo + y_hi)
    beyond = []
    for s in result.sites:
        d, c = s["downrange_nmi"], s["crossrange_nmi"]
        name = f"{s['name'].split(',')[0]} {_probability(s['probability'])}"
        if not (x_lo - mx <= d <= x_hi + mx and y_lo - my <= c <= y_hi + my):
            beyond.append(name)
            continue
        ax.plot(d, c, "k^", ms=5, gid="site", zorder=4)
        ux, uy = (d - x_mid) / (x_hi - x_lo), (c - y_mid) / (y_hi - y_lo)  # outward from the middle
        n = max((ux * ux + uy * uy) ** 0.5, 1e-9)
        ox, oy = LABEL_OFFSET_PT * ux / n, LABEL_OFFSET_PT * uy / n
        ax.annotate(
            name,
            (d, c),
            textcoords="offset points",
            xytext=(ox, oy),
            fontsize="x-small",
            zorder=4,
            ha="left" if ox > 2 else "right" if ox < -2 else "center",
            va="bottom" if oy > 2 else "top" if oy < -2 else "center",
            gid="site_label",
        )
    ax.legend(fontsize="small", loc="best")
    _range_axes(ax, title)
    if beyond:
        ax.annotate(
            fill("Beyond the landings, not drawn: " + ", ".join(beyond), 130),
            (0.5, 0.0),
            xycoords="axes fraction",
            xytext=(0, -30),
            textcoords="offset points",
            ha="center",
            va="top",
            fontsize="x-small",
            gid="caption",
        )
    return fig


def guided_dispersion_figure(result: dict, title=None) -> Figure:
    """A guided dispersion (contracts.guided_dispersion.to_dict): left, both landing clouds about the entry with the
    target; right, the guided ends about the target (down-range and cross-range offsets) with the circles bounding
    each band within R of the terminal-area interface circle and the 3-sigma ellipse, titled with P(within R) and
    its interval."""
    from footprint.core.monte_carlo import ellipse

    fig = Figure(figsize=(12.0, 5.5), layout="constrained")
    wide, near = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    t, clouds = result["target"], result["clouds"]
    styles = {"open_loop": ("0.6", "open loop (nominal guided bank)"), "guided": ("tab:blue", "guided")}
    for mode in ("open_loop", "guided"):
        if mode in clouds:
            color, label = styles[mode]
            c = clouds[mode]
            d = np.array([np.nan if v is None else v for v in c["downrange_nmi"]], float)
            x = np.array([np.nan if v is None else v for v in c["crossrange_nmi"]], float)
            wide.plot(d, x, ".", color=color, ms=2.0, ls="none", label=f"{label}: {np.isfinite(d).sum():,} landings",
                      gid=f"cloud_{mode}", rasterized=True)  # fmt: skip
            if mode == "guided":
                near.plot(d - t["downrange_nmi"], x - t["crossrange_nmi"], ".", color=color, ms=3.0, ls="none",
                          label="guided ends (interface)", gid="cloud_near", rasterized=True)  # fmt: skip
    wide.plot(t["downrange_nmi"], t["crossrange_nmi"], "r*", ms=12, label="target", gid="target", zorder=5)
    wide.legend(fontsize="small", loc="best")
    _range_axes(wide, "Landings about the entry")
    a = np.linspace(0.0, 2.0 * np.pi, 181)
    interface = t.get("interface_range_nmi", 0.0)  # the misses are of the interface circle: the band +- R about it
    for r, ls in zip(result["radii_nmi"], cycle(["-", "--", ":", "-."])):
        for k, about in enumerate(x for x in (interface + r, interface - r) if x > 0.0):
            label = f"{r:g} nmi of the {interface:g} nmi interface" if k == 0 else None
            near.plot(about * np.cos(a), about * np.sin(a), ls=ls, color="k", lw=0.9, label=label, gid="miss_circle")
    landing = result["guided"].get("landing")
    if landing is not None:
        mean = np.array([landing["mean_downrange_nmi"] - t["downrange_nmi"],
                         landing["mean_crossrange_nmi"] - t["crossrange_nmi"]])  # fmt: skip
        ex, ey = ellipse(mean, np.array(landing["covariance_nmi2"]), 3.0)
        near.plot(ex, ey, "-", color="tab:orange", lw=1.2, label=r"3$\sigma$ ellipse", gid="ellipse")
    near.plot(0.0, 0.0, "r+", ms=14, mew=1.5, gid="target_near", zorder=5)
    miss = result["guided"]["miss_nmi"] or {}
    half = max(1.5 * (interface + miss.get("max", 0.0)), 1.2 * (interface + min(result["radii_nmi"])))
    near.set_xlim(-half, half)
    near.set_ylim(-half, half)
    near.set_aspect("equal")
    near.legend(fontsize="small", loc="upper right")
    near.set_xlabel("Down-range past the target (n.mi.)")
    near.set_ylabel("Cross-range left of the target (n.mi.)")
    near.grid(True, color="0.92", lw=0.6)
    words = "; ".join(
        f"P(<= {w['radius_nmi']:g} nmi) {_probability(w['probability'])} [{lo:.3f}, {hi:.3f}]"
        for w in result["guided"]["within"]
        for lo, hi in [w["interval"]]
    )
    near.set_title(fill(f"Guided, miss of the interface: CEP {miss.get('cep', float('nan')):.2f} nmi, "
                        f"p99 {miss.get('p99', float('nan')):.2f}"
                        f" nmi; {words}", 70), fontsize="small")  # fmt: skip
    if title:
        fig.suptitle(title)
    return fig


def guided_footprint_figure(result: dict, title=None) -> Figure:
    """A guided footprint (contracts.guided_footprint) in down-range and cross-range: the true optimal and the
    report's footprints, the undispersed guided one, the guided one under dispersion shaded, the rays from the
    frame's centre; titled with the margins to the outer footprints."""
    fig = Figure(figsize=(10.0, 6.0), layout="constrained")
    ax = fig.add_subplot(1, 1, 1)
    st = result["settings"]
    styles = {
        "optimal": dict(color="k", ls="--", lw=1.2, label="true optimal (collocation)"),
        "report": dict(color="0.45", ls="-", lw=1.2, label="report's single-parameter law"),
        "nominal_guided": dict(color="tab:blue", ls=":", lw=1.4, label="guided, undispersed"),
        "guided": dict(color="tab:blue", ls="-", lw=1.8,
                       label=f"guided: within {st['radius_nmi']:g} nmi in {st['probability']:.0%} of "
                             f"{st['samples']:,} samples"),
    }  # fmt: skip
    f = result["frame"]
    for r in result["rays"]:
        d, c = r["nominal"]["downrange_nmi"], r["nominal"]["crossrange_nmi"]
        ax.plot([f["center_nmi"], d], [0.0, c], color="0.85", lw=0.6, zorder=0)
    for name, style in styles.items():
        ring = result.get(name)
        if ring is None:
            continue
        d, c = ring["downrange_nmi"] + ring["downrange_nmi"][:1], ring["crossrange_nmi"] + ring["crossrange_nmi"][:1]
        ax.plot(d, c, gid=f"ring_{name}", **style)
        if name == "guided":
            ax.fill(d, c, color="tab:blue", alpha=0.15, lw=0)
    ax.plot(0.0, 0.0, "ko", ms=4, label="entry")
    ax.legend(fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3, frameon=False)
    words = [f"guided {result['guided']['area_nmi2'] / 1e6:.1f}M nmi²"]
    for name in ("report", "optimal"):
        m = result.get(f"margin_to_{name}")
        if m is not None:
            inside = "inside at every ray" if m["inside_at_every_ray"] else "NOT inside at every ray"
            words.append(f"margin to the {name} {m['area_nmi2'] / 1e6:.1f}M nmi² ({m['percent']:.0f} %), {inside}")
    _range_axes(ax, title or fill("; ".join(words), 110))
    ax.set_aspect("equal")
    return fig


def opportunities_timeline_figure(result: dict, title=None) -> Figure:
    """Landing opportunities (contracts.opportunities) on a UTC timeline, one row per site: night at the site shaded
    (its night_utc: the sun below -0.833 deg, core.sun), each opportunity at its landing time (filled where it meets
    the rules, open where not), the orbit's ascending nodes as thin lines."""
    from footprint.core.utc import parse_iso as utc  # reads a leap second's 23:59:60 too

    start, end = utc(result["window"]["start_utc"]), utc(result["window"]["end_utc"])
    span_h = (end - start).total_seconds() / 3600.0
    sites = result["sites"]
    fig = Figure(figsize=(11.0, 0.32 * len(sites) + 1.6), layout="constrained")
    ax = fig.add_subplot(1, 1, 1)
    for row, site in enumerate(sites):
        for a, b in site["night_utc"]:
            x0, x1 = ((utc(t) - start).total_seconds() / 3600.0 for t in (a, b))
            ax.fill_between([x0, x1], row - 0.45, row + 0.45, color="0.85", lw=0)
    for node in result["ascending_nodes_utc"]:
        ax.axvline((utc(node) - start).total_seconds() / 3600.0, color="0.7", lw=0.5, zorder=0)
    for taken, style in ((True, dict(color="tab:blue")), (False, dict(facecolor="none", edgecolor="tab:orange"))):
        mine = [o for o in result["opportunities"] if o["meets_rules"] == taken]
        x = [(utc(o["landing_utc"]) - start).total_seconds() / 3600.0 for o in mine]
        ax.scatter(x, [o["site"] for o in mine], s=22, zorder=3, label="meets the rules" if taken else "fails a rule",
                   **style)  # fmt: skip
    ax.set_yticks(range(len(sites)), [s["name"][:32] for s in sites], fontsize=7)
    ax.set_ylim(len(sites) - 0.5, -0.5)
    ax.set_xlim(0.0, span_h + 2.0)
    ax.set_xlabel(f"landing time, hours from {result['window']['start_utc']} (UTC); grey: night at the site")
    e = result["elements"]
    ax.set_title(title or f"Landing opportunities from {e['name'] or e['satellite_number']} ({e['inclination_deg']:.1f}"
                          f" deg); thin lines: ascending nodes", fontsize=10)  # fmt: skip
    ax.legend(loc="lower right", fontsize=8)
    return fig


def _probability(p: float) -> str:
    """Two decimals, three below 0.01 (so a rare reach does not read as 0.00); 0 and 1 exactly."""
    return "0" if p == 0.0 else "1" if p == 1.0 else f"{p:.3f}" if p < 0.01 else f"{p:.2f}"


def two_parameter_figure(fp: Footprint, title=None) -> Figure:
    """Fig. 7: one curve per K set (sigma_f varied along it), the faired outer boundary heavier."""
    fig, ax = _axes(None)
    for (gain, pts), (ls, marker) in zip(fp.sets.items(), cycle(LINE_STYLES[1:])):
        ax.plot(*_xy(pts), ls=ls, marker=marker, ms=4, lw=1.0, label=f"K = {gain:g}", gid="set")
    if fp.outer_boundary:
        d, c = zip(*fp.outer_boundary)
        ax.plot(d, c, "k-", lw=2.4, label="outer boundary", gid="outer_boundary", zorder=3)
    ax.legend(fontsize="small")
    _range_axes(ax, title)
    return fig


def contours_figure(fp: Footprint, title=None) -> Figure:
    """Iso-velocity contours (App. C data set 2, Figs. C-36 to C-54), closed like the boundary."""
    velocities = sorted({c["velocity_fps"] for p in fp.points for c in p.contours}, reverse=True)
    if not velocities:
        raise ValueError("the footprint carries no iso-velocity contours: generate it with contours_fps")
    fig, ax = _axes(None)
    ax.axhline(0.0, color="0.85", lw=0.8, zorder=0)
    ax.plot(*_closed(fp.points), "k-", lw=2.0, label="end of flight", gid="boundary")
    for v, (ls, _) in zip(velocities, cycle(LINE_STYLES[1:])):
        at = [c for p in fp.points for c in p.contours if c["velocity_fps"] == v]
        d = [c["downrange_nmi"] for c in at] + [at[0]["downrange_nmi"]]
        x = [c["crossrange_nmi"] for c in at] + [at[0]["crossrange_nmi"]]
        ax.plot(d, x, ls=ls, lw=1.1, label=f"{v:,.0f} ft/s", gid="contour")
    ax.legend(fontsize="small", title="velocity")
    _range_axes(ax, title)
    return fig


# ---------------------------------------------------------------------------------------- trajectories
def histories_figure(trajectories: dict[str, Trajectory], title=None) -> Figure:
    """Altitude-velocity (Figs. 17, 18), altitude and bank against time, and the ground track."""
    fig = Figure(figsize=(10.0, 7.5), layout="constrained")
    axes = fig.subplots(2, 2)
    panels = [
        ("velocity_fps", 1e-3, "Velocity (1000 ft/s)", "altitude_ft", 1e-3, "Altitude (1000 ft)"),
        ("time_s", 1.0, "Time (s)", "altitude_ft", 1e-3, "Altitude (1000 ft)"),
        ("time_s", 1.0, "Time (s)", "bank_deg", 1.0, "Bank angle (deg)"),
        ("downrange_nmi", 1.0, DOWNRANGE_LABEL, "crossrange_nmi", 1.0, CROSSRANGE_LABEL),
    ]
    for ax, (xk, xs, xl, yk, ys, yl) in zip(axes.flat, panels):
        for (name, t), (ls, _) in zip(trajectories.items(), cycle(LINE_STYLES)):
            ax.plot(t.history[xk] * xs, t.history[yk] * ys, ls=ls, lw=1.1, label=name)
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.grid(True, color="0.9")
        _thousands(ax)
    axes[0, 0].legend(fontsize="small")
    if title:
        fig.suptitle(title)
    return fig


def bank_schedule_figure(schedules: dict[str, tuple], title=None) -> Figure:
    """Bank angle against heading, or the remaining heading change zeta, 90 -> 0 deg left to right
    (Figs. 2, 5, 6, 8). Each schedule is (zeta_deg, bank_deg)."""
    fig, ax = _axes(None, figsize=(7.0, 5.0))
    lo = hi = None
    for (name, (zeta_deg, bank_deg)), (ls, _) in zip(schedules.items(), cycle(LINE_STYLES)):
        ax.plot(zeta_deg, bank_deg, ls=ls, lw=1.3, label=name)
        lo = min(min(zeta_deg), 0.0 if lo is None else lo)
        hi = max(max(zeta_deg), 90.0 if hi is None else hi)
    ax.set_xlim(hi if hi is not None else 90.0, lo if lo is not None else 0.0)  # reversed, as the report
    ax.set_xlabel(r"Heading, or remaining heading change $\zeta$ (deg)")
    ax.set_ylabel(r"Bank angle $\phi_B$ (deg)")
    ax.grid(True, color="0.9")
    if schedules:
        ax.legend(fontsize="small")
    if title:
        ax.set_title(title)
    return fig


def pullout_carpet_figure(rows, title=None) -> Figure:
    """Pull-out altitude (gamma = 0) against entry angle, one curve per entry velocity (Fig. 16, C-34),
    and beside it the down-range to pull-out where the rows give it (Fig. C-35)."""
    rows = [r for r in rows if r.get("pullout_altitude_ft") is not None]  # skipped out: never pulled out
    with_range = any(r.get("pullout_downrange_nmi") is not None for r in rows)
    fig = Figure(figsize=(11.0 if with_range else 6.5, 5.0), layout="constrained")
    axes = fig.subplots(1, 2 if with_range else 1, squeeze=False)[0]
    panels = [
        ("pullout_altitude_ft", 1e-3, "Pull-out altitude (1000 ft)"),
        ("pullout_downrange_nmi", 1.0, "Down-range to pull-out (n.mi.)"),
    ][: len(axes)]
    velocities = sorted({r["entry_velocity_fps"] for r in rows})
    for ax, (key, scale, label) in zip(axes, panels):
        for v, (ls, marker) in zip(velocities, cycle(LINE_STYLES)):
            pts = sorted(
                (r["entry_gamma_deg"], r[key] * scale)
                for r in rows
                if r["entry_velocity_fps"] == v and r.get(key) is not None
            )
            if pts:
                ax.plot(*zip(*pts), ls=ls, marker=marker, ms=4, lw=1.2, label=f"{v:,.0f} ft/s")
        ax.set_xlabel(r"Entry flight-path angle $\gamma_e$ (deg)")
        ax.set_ylabel(label)
        ax.grid(True, color="0.9")
        _thousands(ax)
        ax.legend(fontsize="small", title="entry velocity")
    if title:
        fig.suptitle(title)
    return fig


# ------------------------------------------------------------------------------------------------ files
# the searched tables' abscissae (constrained.NODE_LABELS) as axis labels
NODE_AXES = {
    "zeta": "Remaining heading change ζ (deg)",
    "heading_deg": "Heading σ (deg)",
    "time_s": "Time (s)",
    "velocity_fps": "Earth-relative velocity (ft/s)",
    "energy_ft": "Energy height h + V²/2g₀ (ft)",
}


def optimization_figure(result, title=None) -> Figure:
    """Fig. 3: payoff against trajectories flown, and the optimum's tables, each against its own abscissa
    (the bank against zeta as in Fig. 2, its axis running 90 -> -15 deg as the report's does)."""
    tables = _tables_of(result)
    fig = Figure(figsize=(5.5 * (1 + len(tables)), 4.5))
    ax1, *axes = fig.subplots(1, 1 + len(tables))
    h = result.history
    ax1.plot([e["trajectories"] for e in h], [e["payoff"] for e in h], "-k")
    ax1.set_xlabel("Trajectories flown")
    ax1.set_ylabel("Best payoff so far (its own unit)")
    ax1.grid(alpha=0.3)
    for ax, ((angle, label), points) in zip(axes, tables.items()):
        x, y = zip(*points)
        ax.plot(x, y, "o-k")
        if label == "zeta":
            ax.set_xlim(max(x), min(x))
        ax.set_xlabel(NODE_AXES[label])
        ax.set_ylabel(f"{'Bank angle' if angle == 'bank' else 'Angle of attack'} (deg)")
        ax.grid(alpha=0.3)
    fig.suptitle(
        title
        or f"{result.method}: payoff {result.payoff:,.1f}, {result.trajectories} trajectories"
        + ("" if result.feasible else " (infeasible)")
    )
    return fig


def collocation_figure(result, title=None) -> Figure:
    """A true optimum (core.collocation): altitude, alpha and bank, and (with heating) the temperature against
    time, the NLP's points beside the re-flight's end (the dashed line marks the flown final time)."""
    h = result.history
    panels = [
        ("altitude_ft", "Altitude (ft)"),
        ("alpha_deg", "Angle of attack (deg)"),
        ("bank_deg", "Bank angle (deg)"),
    ]
    if "temperature_R" in h and np.all(np.isfinite(h["temperature_R"])):
        panels.append(("temperature_R", "Radiation-equilibrium temperature (degR)"))
    elif "heat_rate_btu_ft2_s" in h:
        panels.append(("heat_rate_btu_ft2_s", "Heat rate (Btu/ft^2/s)"))
    fig = Figure(figsize=(11.0, 3.2 * ((len(panels) + 1) // 2)))
    axes = fig.subplots((len(panels) + 1) // 2, 2, squeeze=False).ravel()
    for ax, (key, label) in zip(axes, panels):
        ax.plot(h["time_s"], h[key], "-k", lw=1.2)
        if result.refly is not None:
            ax.axvline(result.refly["flight_time_s"], color="0.5", ls="--", lw=0.8)
        ax.set_xlabel("Time (s)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    for ax in axes[len(panels) :]:
        ax.set_visible(False)
    s, a = result.summary, result.agreement
    agree = (
        ""
        if a is None
        else (
            f"; re-flown: {a['latitude_deg']:.4f} deg lat, {a['longitude_deg']:.4f} deg lon, "
            f"{100 * a['downrange_rel']:.3f} % down-range"
        )
    )
    fig.suptitle(
        title
        or f"collocation {result.status}: down-range {s['downrange_nmi']:,.1f} nmi, cross-range "
        f"{s['crossrange_nmi']:,.1f} nmi, {s['flight_time_s']:,.0f} s{agree}",
        fontsize=9,
    )
    fig.tight_layout()
    return fig


def _tables_of(result) -> dict:
    """{(angle, abscissa label): [(node, value)...]} from parameter names "<angle>_deg_at_<label>_<node>"."""
    tables = {}
    for name, value in zip(result.names, result.params):
        angle, rest = name.split("_deg_at_", 1)
        label, node = rest.rsplit("_", 1)
        tables.setdefault((angle, label), []).append((float(node), float(value)))
    return tables


def save(fig: Figure, path) -> Path:
    """Write PNG (150 dpi) or SVG by the suffix, making the folder; the figure is closed afterwards."""
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in ("png", "svg"):
        raise ValueError(f"figure file {path.name!r}: suffix must be .png or .svg")
    path.parent.mkdir(parents=True, exist_ok=True)
    meta = {"Date": None} if fmt == "svg" else {}  # reproducible SVG
    fig.savefig(path, format=fmt, dpi=PNG_DPI, bbox_inches="tight", metadata=meta)
    plt.close(fig)  # a no-op unless the figure came from pyplot
    return path


# ---------------------------------------------------------------------------------------------- helpers
def _axes(ax, figsize=(8.0, 6.0)):
    if ax is not None:
        return ax.figure, ax
    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.add_subplot()


def _interior(fp: Footprint) -> list[FootprintPoint]:
    return list(getattr(fp, "interior", None) or [])


def _thousands(ax):
    """Tick labels with thousands separators (14,000 n.mi.), whole numbers where the ticks are."""
    for axis in (ax.xaxis, ax.yaxis):
        axis.set_major_formatter(StrMethodFormatter("{x:,g}"))


def _xy(points: list[FootprintPoint]):
    return [p.downrange_nmi for p in points], [p.crossrange_nmi for p in points]


def _closed(points: list[FootprintPoint]):
    """The boundary's vertices with the first repeated at the end (the polygon closes)."""
    d, c = _xy(points)
    return d + d[:1], c + c[:1]


def _range_axes(ax, title):
    ax.set_xlabel(DOWNRANGE_LABEL)
    ax.set_ylabel(CROSSRANGE_LABEL)
    ax.grid(True, color="0.92", lw=0.6)
    ax.margins(x=0.1, y=0.08)
    _thousands(ax)
    if title:
        ax.set_title(title)


def parameter_label(setting: ControlSetting) -> str:
    """A point's control setting as the report writes it: phi0, K and sigma_f, phi, or the turn; none for a
    collocation footprint's point (its controls are tables of 101 nodes)."""
    s = setting
    if s.collocated:
        return ""
    if s.min_range is not None:
        return "zero lift" if s.min_range == "zero_lift" else r"$C_{L\,max}$"
    if s.sigma_f_deg is not None:
        return rf"K={s.bank_gain:.3g}, $\sigma_f$={s.sigma_f_deg:.3g}°"
    if s.bank0_deg is not None:
        return rf"$\phi_0$={s.bank0_deg:.3g}°"
    if s.bank_deg is not None:
        return rf"$\phi$={s.bank_deg:.3g}°"
    if s.turn_deg is not None:
        return rf"$\Delta\sigma$={s.turn_deg:.3g}°" + (" (max)" if s.until else "")
    return s.words()


def _label_points(ax, fp: Footprint):
    """Label the left half and the axis, each label pushed outward from the footprint's middle."""
    d_lo, d_hi = fp.min_downrange_nmi, fp.max_downrange_nmi
    d_mid, d_span = 0.5 * (d_lo + d_hi), max(d_hi - d_lo, 1.0)
    c_span = max(max(abs(p.crossrange_nmi) for p in fp.points), 1.0)
    for p in fp.points + _interior(fp):
        label = parameter_label(p.parameter)
        if p.side == "right" or not label:
            continue
        if p.parameter.min_range is not None:  # below the axis, clear of the steepest-bank point beside it
            ox, oy = 0.5 * LABEL_OFFSET_PT, -LABEL_OFFSET_PT
        else:
            ux, uy = (p.downrange_nmi - d_mid) / d_span, p.crossrange_nmi / c_span
            n = max((ux * ux + uy * uy) ** 0.5, 1e-9)
            ox, oy = LABEL_OFFSET_PT * ux / n, LABEL_OFFSET_PT * uy / n
        ax.annotate(
            label,
            (p.downrange_nmi, p.crossrange_nmi),
            xytext=(ox, oy),
            textcoords="offset points",
            fontsize=7.5,
            ha="left" if ox > 2 else "right" if ox < -2 else "center",
            va="bottom" if oy > 2 else "top" if oy < -2 else "center",
        )


def _caption(ax, fp: Footprint):
    reflected, inside = sum(p.mirrored for p in fp.points), len(_interior(fp))
    work = f"{fp.trajectories} trajectories"
    if fp.method == "collocation":
        work = (
            f"{fp.trajectories} IPOPT solves, re-flown within "
            f"{max(p.parameter.agreement_deg or 0.0 for p in fp.points):.2g}°"
        )
    text = (
        f"{fp.method.replace('_', ' ')}  ·  area {fp.area_nmi2:,.0f} nmi²  ·  {work}"
        + (f"  ·  {reflected} points reflected" if reflected else "")
        + (f"  ·  {inside} inside (×)" if inside else "")
    )
    ax.annotate(
        text,
        (0.5, 0.0),
        xycoords="axes fraction",
        xytext=(0, -30),
        textcoords="offset points",
        ha="center",
        va="top",
        fontsize="small",
        gid="caption",
    )

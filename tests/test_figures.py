"""Figures (footprint.pictures.figures): what is drawn is the data, in the report's axes and units; files are valid."""

import xml.etree.ElementTree as ET
from dataclasses import replace
from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.colors import to_rgb

from footprint.contracts import parse
from footprint.core import footprints as F
from footprint.core import method_settings as S
from footprint.core.setting import ControlSetting
from footprint.core.trajectory import Trajectory
from footprint.pictures import figures as G
from tests.authorities.report import table2_entry, table2_stop

TABLE2_CASE = {"vehicle": {"builtin": "lod-1.89"}, "entry": table2_entry(), "stop": table2_stop()}
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
MIN_FILE_BYTES = 5_000  # a drawn footprint, not an empty canvas


def pt(d, c, side="left", parameter=None, mirrored=False, contours=()):
    return F.FootprintPoint(
        parameter=ControlSetting.of(parameter or {}),
        side=side,
        downrange_nmi=d,
        crossrange_nmi=c,
        flight_time_s=1000.0,
        latitude_deg=0.0,
        longitude_deg=0.0,
        heading_deg=90.0,
        final_velocity_fps=1000.0,
        final_altitude_ft=50_000.0,
        pullout_altitude_ft=2e5,
        stop_reason="altitude",
        contours=contours,
        mirrored=mirrored,
    )


def contour(v, d, c):
    return {"velocity_fps": v, "downrange_nmi": d, "crossrange_nmi": c}


def hand_footprint(with_contours=False):
    """Front axis point, two left points, the zero-lift point, the left points reflected."""

    def cs(d, c):  # iso-velocity points short of the end; the 3,000 nmi point never slows to 2,000 ft/s
        if not with_contours:
            return ()
        out = (contour(6000.0, d - 300, 0.8 * c),)
        return out + ((contour(2000.0, d - 50, 0.95 * c),) if d != 3000.0 else ())

    left = [
        pt(2500.0, 900.0, parameter={"bank0_deg": 45.0, "bank_gain": 0.5}, contours=cs(2500.0, 900.0)),
        pt(900.0, 600.0, parameter={"bank0_deg": 90.0, "bank_gain": 1.0}, contours=cs(900.0, 600.0)),
    ]
    right = [
        pt(
            p.downrange_nmi,
            -p.crossrange_nmi,
            "right",
            p.parameter,
            True,
            tuple(c | {"crossrange_nmi": -c["crossrange_nmi"]} for c in p.contours),
        )
        for p in left
    ]
    points = (
        [pt(3000.0, 0.0, "axis", {"bank0_deg": 0.0, "bank_gain": 0.0}, contours=cs(3000.0, 0.0))]
        + left
        + [pt(500.0, 0.0, "axis", {"min_range": "zero_lift"}, contours=cs(500.0, 0.0))]
        + right[::-1]
    )
    return F.Footprint(
        method="single_parameter",
        points=points,
        area_nmi2=F.area_nmi2(points),
        trajectories=4,
        entry={"latitude_deg": 0.0, "longitude_deg": 0.0, "heading_deg": 90.0},
    )


def lines(ax, gid):
    return [ln for ln in ax.get_lines() if ln.get_gid() == gid]


def vertices(line):
    return list(zip(np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)))


def down_cross(points):
    return [(p.downrange_nmi, p.crossrange_nmi) for p in points]


@pytest.fixture(scope="module")
def table2_footprint():
    """One real single-parameter footprint (Fig. 12's L/D 1.89 vehicle, Table 2 entry), with two contours."""
    spec = parse("case", TABLE2_CASE).to_spec()
    return F.single_parameter(
        spec, S.SingleParameter(bank0_deg=(0, 30, 60, 90, 120, 150), contours_fps=(6000.0, 10000.0))
    )


# ---------------------------------------------------------------------------------------- one footprint
def test_boundary_is_the_footprints_points_in_order_and_closed():
    fp = hand_footprint()
    (boundary,) = lines(G.footprint_figure(fp).axes[0], "boundary")
    assert vertices(boundary) == down_cross(fp.points) + down_cross(fp.points[:1])


def test_flown_points_are_filled_and_reflected_points_hollow():
    fp = hand_footprint()
    ax = G.footprint_figure(fp).axes[0]
    (flown,), (mirrored,) = lines(ax, "flown"), lines(ax, "mirrored")
    assert vertices(flown) == down_cross([p for p in fp.points if not p.mirrored])
    assert vertices(mirrored) == down_cross([p for p in fp.points if p.mirrored])
    assert mirrored.get_markerfacecolor() == "none" and flown.get_markerfacecolor() != "none"


def test_axes_carry_the_reports_range_units():
    ax = G.footprint_figure(hand_footprint(), title="L/D 1.89").axes[0]
    assert ax.get_xlabel() == "Down-range (n.mi.)" and ax.get_ylabel() == "Cross-range (n.mi.)"
    assert ax.get_title() == "L/D 1.89"


def test_left_half_and_axis_points_are_labelled_by_their_parameter_and_the_right_half_is_not():
    fp = hand_footprint()
    ax = G.footprint_figure(fp).axes[0]
    labels = [t.get_text() for t in ax.texts if t.get_gid() != "caption"]
    assert labels == [r"$\phi_0$=0°", r"$\phi_0$=45°", r"$\phi_0$=90°", "zero lift"]
    assert not [t for t in G.footprint_figure(fp, label_points=False).axes[0].texts if t.get_gid() != "caption"]


def test_caption_gives_method_area_with_separators_and_trajectory_count():
    fp = hand_footprint()
    (caption,) = [t for t in G.footprint_figure(fp).axes[0].texts if t.get_gid() == "caption"]
    text = caption.get_text()
    assert fp.area_nmi2 > 1_000_000.0  # so the separators show
    assert "single parameter" in text and f"{fp.area_nmi2:,.0f} nmi²" in text
    assert "4 trajectories" in text and "2 points reflected" in text


def test_the_initial_great_circle_is_drawn_faint():
    ax = G.footprint_figure(hand_footprint()).axes[0]
    (axis,) = [ln for ln in ax.get_lines() if list(ln.get_ydata()) == [0.0, 0.0]]
    assert min(to_rgb(axis.get_color())) > 0.5  # lighter than mid-grey


def test_points_inside_the_boundary_are_drawn_and_counted():
    fp = hand_footprint()
    inside = pt(700.0, 0.0, "axis", {"min_range": "cl_max"})
    fp.interior = [inside]
    ax = G.footprint_figure(fp).axes[0]
    (interior,) = lines(ax, "interior")
    assert vertices(interior) == down_cross([inside])
    assert r"$C_{L\,max}$" in [t.get_text() for t in ax.texts]


def test_drawing_into_a_given_axes_returns_its_figure():
    fig = plt.figure()
    try:
        ax = fig.add_subplot(1, 2, 2)
        assert G.footprint_figure(hand_footprint(), ax=ax) is fig
        assert lines(ax, "boundary")
    finally:
        plt.close(fig)


@pytest.mark.parametrize(
    "parameter, label",
    [
        ({"bank0_deg": 45.0, "bank_gain": 0.5}, r"$\phi_0$=45°"),
        ({"bank_gain": 0.67, "sigma_f_deg": -15.0}, r"K=0.67, $\sigma_f$=-15°"),
        ({"bank_deg": 30.0, "turn_deg": 90.0}, r"$\phi$=30°"),
        ({"turn_deg": 11.448540987}, r"$\Delta\sigma$=11.4°"),
        ({"turn_deg": 38.2, "until": "wings_level"}, r"$\Delta\sigma$=38.2° (max)"),
        ({"min_range": "zero_lift"}, "zero lift"),
        ({"min_range": "cl_max"}, r"$C_{L\,max}$"),
    ],
)
def test_parameter_labels_as_the_report_names_them(parameter, label):
    assert G.parameter_label(ControlSetting(**parameter)) == label


# ------------------------------------------------------------------------------------ several footprints
def test_overlay_has_one_curve_per_footprint_legend_from_keys_and_distinct_styles():
    a, b = hand_footprint(), hand_footprint()
    b.points = [replace(p, downrange_nmi=p.downrange_nmi * 1.1) for p in b.points]
    family = {f"γ = -{g}°": b if g == 2 else a for g in range(1, len(G.LINE_STYLES) + 1)}  # the whole cycle
    ax = G.footprints_figure(family, title="Fig. 15").axes[0]
    curves = lines(ax, "footprint")
    assert len(curves) == len(family)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == list(family)
    assert vertices(curves[1]) == down_cross(b.points) + down_cross(b.points[:1])
    styles = {(str(c.get_linestyle()), c.get_marker()) for c in curves}
    assert len(styles) == len(curves)  # told apart without colour


def test_two_parameter_sets_each_a_curve_and_the_outer_boundary_heaviest():
    fp = hand_footprint()
    fp.sets = {0.5: fp.points[:2], 1.0: [fp.points[0], fp.points[2]]}
    fp.outer_boundary = [(900.0, 0.0), (900.0, 600.0), (2500.0, 900.0), (3000.0, 0.0)]
    ax = G.two_parameter_figure(fp).axes[0]
    sets, (outer,) = lines(ax, "set"), lines(ax, "outer_boundary")
    assert [vertices(s) for s in sets] == [down_cross(v) for v in fp.sets.values()]
    assert all(s.get_marker() not in ("", "None", None) for s in sets)
    assert vertices(outer) == fp.outer_boundary
    assert outer.get_linewidth() > max(s.get_linewidth() for s in sets)
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["K = 0.5", "K = 1", "outer boundary"]


# --------------------------------------------------------------------------------------------- contours
def test_one_closed_contour_per_velocity_through_the_points_that_reached_it():
    fp = hand_footprint(with_contours=True)
    ax = G.contours_figure(fp).axes[0]
    contours = {ln.get_label(): ln for ln in lines(ax, "contour")}
    assert list(contours) == ["6,000 ft/s", "2,000 ft/s"]  # fastest (innermost) first
    for label, v in (("6,000 ft/s", 6000.0), ("2,000 ft/s", 2000.0)):
        expected = [
            (c["downrange_nmi"], c["crossrange_nmi"]) for p in fp.points for c in p.contours if c["velocity_fps"] == v
        ]
        assert vertices(contours[label]) == expected + expected[:1]
    assert len(vertices(contours["2,000 ft/s"])) == len(fp.points)  # one point missed it, the line closes


def test_contours_need_a_footprint_generated_with_them():
    with pytest.raises(ValueError, match="contours_fps"):
        G.contours_figure(hand_footprint())


# ----------------------------------------------------------------------------------------- trajectories
def synthetic_trajectory(scale):
    t = np.linspace(0.0, 2000.0, 50)
    h = {
        k: np.zeros_like(t)
        for k in (
            "gamma_deg",
            "heading_deg",
            "latitude_deg",
            "longitude_deg",
            "alpha_deg",
            "mach",
            "dynamic_pressure_psf",
            "cl",
            "cd",
            "lift_to_drag",
        )
    }
    h |= {
        "time_s": t,
        "altitude_ft": 300_000.0 - 100.0 * t * scale,
        "velocity_fps": 24_000.0 - 10.0 * t,
        "bank_deg": 45.0 * scale * (1 - t / 2000.0),
        "downrange_nmi": 3.0 * t,
        "crossrange_nmi": 0.1 * t * scale,
    }
    return Trajectory(summary={}, history=h)


def test_histories_panels_plot_the_histories_in_the_reports_units():
    trajs = {"K = 0.5": synthetic_trajectory(1.0), "K = 1.0": synthetic_trajectory(1.2)}
    fig = G.histories_figure(trajs, title="histories")
    hv, ht, bank, track = fig.axes
    assert (hv.get_xlabel(), hv.get_ylabel()) == ("Velocity (1000 ft/s)", "Altitude (1000 ft)")
    assert (ht.get_xlabel(), bank.get_ylabel()) == ("Time (s)", "Bank angle (deg)")
    assert (track.get_xlabel(), track.get_ylabel()) == ("Down-range (n.mi.)", "Cross-range (n.mi.)")
    assert all(len(ax.get_lines()) == len(trajs) for ax in fig.axes)
    h = trajs["K = 1.0"].history
    line = hv.get_lines()[1]
    assert np.allclose(line.get_xdata(), h["velocity_fps"] / 1000.0)
    assert np.allclose(line.get_ydata(), h["altitude_ft"] / 1000.0)
    assert [t.get_text() for t in hv.get_legend().get_texts()] == list(trajs)


def test_bank_schedules_run_from_90_to_0_deg_left_to_right():
    zeta = np.linspace(90.0, 0.0, 31)
    ax = G.bank_schedule_figure({f"K = {k}": (zeta, np.minimum(k * zeta, 85.0)) for k in (0.5, 1.5)}).axes[0]
    assert ax.xaxis_inverted() and ax.get_xlim() == (90.0, 0.0)
    assert "(deg)" in ax.get_xlabel() and "(deg)" in ax.get_ylabel()
    assert np.allclose(ax.get_lines()[1].get_ydata(), np.minimum(1.5 * zeta, 85.0))


def test_bank_schedule_axis_extends_past_zero_for_a_negative_final_heading():
    zeta = np.linspace(90.0, -45.0, 10)  # Fig. 6: sigma_f = -45 deg
    ax = G.bank_schedule_figure({"K = 0.5": (zeta, 0.5 * (zeta + 45.0))}).axes[0]
    assert ax.get_xlim() == (90.0, -45.0)


def optimum(names, params):
    """An optimize.Result's drawn fields, by hand."""
    return SimpleNamespace(
        names=tuple(names),
        params=np.asarray(params, dtype=float),
        method="creep_pattern",
        history=[{"trajectories": n, "payoff": 30.0 + n} for n in (1, 2, 3)],
        payoff=33.0,
        trajectories=3,
        feasible=True,
    )


def test_an_optimum_draws_each_table_against_its_own_abscissa():
    names = [
        "bank_deg_at_energy_ft_177000",
        "bank_deg_at_energy_ft_10445000",
        "alpha_deg_at_time_s_0",
        "alpha_deg_at_time_s_900.5",
        "alpha_deg_at_time_s_2000",
    ]
    _, bank, alpha = G.optimization_figure(optimum(names, [5.0, 73.0, 17.0, 17.5, 16.0])).axes
    assert list(bank.get_lines()[0].get_xdata()) == [177_000.0, 10_445_000.0]
    assert "Energy height" in bank.get_xlabel() and bank.get_ylabel() == "Bank angle (deg)"
    assert list(alpha.get_lines()[0].get_xdata()) == [0.0, 900.5, 2_000.0]
    assert list(alpha.get_lines()[0].get_ydata()) == [17.0, 17.5, 16.0]
    assert alpha.get_xlabel() == "Time (s)" and alpha.get_ylabel() == "Angle of attack (deg)"


def test_the_reports_bank_table_is_drawn_from_90_to_minus_15_deg():
    fig = G.optimization_figure(optimum([f"bank_deg_at_zeta_{z}" for z in range(-15, 91, 15)], np.arange(8.0)))
    assert len(fig.axes) == 2 and fig.axes[1].get_xlim() == (90.0, -15.0)


def test_pullout_carpet_one_curve_per_entry_velocity_sorted_by_angle():
    rows = [
        {"entry_velocity_fps": v, "entry_gamma_deg": g, "pullout_altitude_ft": 1000.0 * (200 + g + v / 1000)}
        for v in (24_000.0, 20_000.0)
        for g in (-5.0, -1.5, -10.0)
    ]
    rows.append({"entry_velocity_fps": 20_000.0, "entry_gamma_deg": -25.0, "pullout_altitude_ft": None})  # skipped
    fig = G.pullout_carpet_figure(rows)
    (ax,) = fig.axes
    assert ax.get_ylabel() == "Pull-out altitude (1000 ft)" and "(deg)" in ax.get_xlabel()
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["20,000 ft/s", "24,000 ft/s"]
    slow = ax.get_lines()[0]
    assert list(slow.get_xdata()) == [-10.0, -5.0, -1.5]
    assert np.allclose(slow.get_ydata(), [200 - 10 + 20, 200 - 5 + 20, 200 - 1.5 + 20])


def test_pullout_carpet_adds_the_pullout_range_panel_when_given():
    rows = [
        {"entry_velocity_fps": 20_000.0, "entry_gamma_deg": g, "pullout_altitude_ft": 1.5e5, "pullout_downrange_nmi": r}
        for g, r in ((-2.0, 470.0), (-10.0, 190.0))
    ]
    alt, rng = G.pullout_carpet_figure(rows).axes
    assert rng.get_ylabel() == "Down-range to pull-out (n.mi.)"
    assert list(rng.get_lines()[0].get_ydata()) == [190.0, 470.0]


# ------------------------------------------------------------------------------------------------ files
def test_save_writes_a_png_and_an_svg_and_makes_the_folder(tmp_path):
    png = G.save(G.footprint_figure(hand_footprint()), tmp_path / "new" / "fp.png")
    svg = G.save(G.footprint_figure(hand_footprint()), tmp_path / "new" / "fp.svg")
    assert png.read_bytes()[:8] == PNG_MAGIC and png.stat().st_size > MIN_FILE_BYTES
    root = ET.parse(svg).getroot()
    assert root.tag.endswith("svg") and svg.stat().st_size > MIN_FILE_BYTES


def test_save_closes_a_pyplot_figure_and_refuses_other_formats(tmp_path):
    fig = plt.figure()
    G.save(fig, tmp_path / "empty.png")
    assert fig.number not in plt.get_fignums()
    with pytest.raises(ValueError, match=r"\.png or \.svg"):
        G.save(G.footprint_figure(hand_footprint()), tmp_path / "fp.jpg")
    assert not (tmp_path / "fp.jpg").exists()


# ----------------------------------------------------------------------------------------- end to end
def test_a_flown_footprint_is_drawn_point_for_point(table2_footprint, tmp_path):
    fp = table2_footprint
    ax = G.footprint_figure(fp, title="L/D 1.89").axes[0]
    (boundary,) = lines(ax, "boundary")
    assert vertices(boundary) == down_cross(fp.points) + down_cross(fp.points[:1])
    labelled = [p for p in fp.points + fp.interior if p.side != "right"]
    assert len([t for t in ax.texts if t.get_gid() != "caption"]) == len(labelled) == 7  # 6 banks, zero lift
    path = G.save_footprint_plot(fp, tmp_path / "fp.png")
    assert path.read_bytes()[:8] == PNG_MAGIC and path.stat().st_size > MIN_FILE_BYTES


def test_a_flown_footprints_contours_lie_inside_its_boundary(table2_footprint):
    ax = G.contours_figure(table2_footprint).axes[0]
    contours = lines(ax, "contour")
    assert [c.get_label() for c in contours] == ["10,000 ft/s", "6,000 ft/s"]
    for c in contours:  # reached before the end of flight: shorter down-range than the boundary's nose
        assert max(c.get_xdata()) < table2_footprint.max_downrange_nmi

"""AFWAL-TR-82-3036 Section IV on our footprints: Figs. 31-33 and the earth-rotation comparison.

    python3 scripts/section_iv_figures.py     # docs/figures/fig31_*.png, fig32_*.png, fig33_*.png, docs/maps.md

Footprints: single-parameter (Section II.6), Table 2 entry (364,800 ft, 24,480 ft/s, gamma -2 deg, east at
0 deg latitude and longitude), (L/D)max, stop at 50,000 ft, flown on a NON-rotating oblate earth as the
report's Section IV takes them ("the flight time is obtained from the nonrotating trajectory runs"). For
Figs. 31 and 32 only the left half is flown and the right half is drawn by mirror, as the report's display
program did. Fig. 33 and the table fly both halves (the oblate earth's odd zonal term makes them differ by
a fraction of a mile) and compare the first-order shift with the footprint flown again on the rotating
earth from the moved geometry (footprint.core.rotation).
"""

import sys
import time
from pathlib import Path

import numpy as np

from footprint.contracts import parse
from footprint.core.footprint_methods import footprint
from footprint.core.rotation import VELOCITY_FRAMES, approximate_points, approximate_vs_exact
from footprint.core.sphere import Reference, heading_for_inclination, mirror, move
from footprint.pictures.figures import save
from footprint.pictures.maps import footprint_layer, panels_figure

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root, for tests.authorities
from tests.authorities.report import REPORT, table2_entry, table2_stop  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
FIGURES = ROOT / "docs" / "figures"
DOC = ROOT / "docs" / "maps.md"
TABLE2_ENTRY = table2_entry()
TABLE2_INERTIAL_FPS = int(REPORT["table2.inertial_velocity_fps"].value)  # the same entry's inertial speed
ORIGIN_EAST = Reference(0.0, 0.0, 90.0)


def study(vehicle, velocity_fps=24_480, mirror_half=True):
    return parse(
        "footprint",
        {
            "case": {
                "vehicle": {"builtin": vehicle},
                "planet": {"rotating": False},
                "entry": TABLE2_ENTRY | {"velocity_fps": velocity_fps},
                "stop": table2_stop(),
            },
            "method": "single_parameter",
            "mirror": mirror_half,
        },
    )


def fly(st):
    return footprint(st.case.to_spec(), st.to_settings())


def whole_by_mirror(half):
    """Boundary of the whole footprint from its left half: the half in order (front, left side, back), then
    the left side reflected across the initial great circle, back to front (Section IV: "only half of a
    symmetrical footprint ... and computer generate the other half")."""
    lat = np.array([p.latitude_deg for p in half.points])
    lon = np.array([p.longitude_deg for p in half.points])
    down = np.array([p.downrange_nmi for p in half.points])
    side = np.array([p.side == "left" for p in half.points])
    mlat, mlon = mirror(lat[side], lon[side], ORIGIN_EAST)
    return (
        np.concatenate([lat, mlat[::-1]]),
        np.concatenate([lon, mlon[::-1]]),
        np.concatenate([down, down[side][::-1]]),
    )


def moved_layer(lat, lon, down, dst, **style):
    mlat, mlon = move(lat, lon, ORIGIN_EAST, dst)
    return footprint_layer(mlat, mlon, reference=dst, downrange_nmi=down, shade=True, **style)


def heading_label(h):
    return {
        90.0: "heading 90° (east, inclination 0°)",
        30.0: "heading 30° (inclination 60°)",
        -90.0: "heading −90° (west)",
    }[h]


# ------------------------------------------------------------------------------------------- figures
def fig31(half):
    lat, lon, down = whole_by_mirror(half)
    cyl = []
    for tag, h in (("a", 90.0), ("b", 30.0), ("c", -90.0)):
        dst = Reference(0.0, 0.0, h)
        cyl.append(
            {
                "projection": "cylindrical",
                "title": f"({tag}) L/D 1.89, {heading_label(h)}",
                "layers": [moved_layer(lat, lon, down, dst, marker="o")],
                "legend": False,
            }
        )
    save(
        panels_figure(cyl, ncols=1, title="Fig. 31 (a-c): L/D 1.89 footprint, cylindrical equidistant"),
        FIGURES / "fig31_cylindrical.png",
    )
    ortho = []
    for tag, inc in (("d", 0.0), ("e", 60.0)):
        dst = Reference(0.0, 0.0, float(heading_for_inclination(0.0, inc)))
        ortho.append(
            {
                "projection": "orthographic",
                "title": f"({tag}) inclination {inc:g}°",
                "layers": [moved_layer(lat, lon, down, dst, marker="o")],
                "legend": False,
            }
        )
    save(
        panels_figure(ortho, ncols=2, title="Fig. 31 (d, e): L/D 1.89 footprint, orthographic"),
        FIGURES / "fig31_orthographic.png",
    )


def fig32(half):
    lat, lon, down = whole_by_mirror(half)
    panels = {"cylindrical": [], "orthographic": []}
    tags = iter("abcd")
    for projection in panels:
        for inc in (0.0, 30.0):
            dst = Reference(0.0, 0.0, float(heading_for_inclination(0.0, inc)))
            panels[projection].append(
                {
                    "projection": projection,
                    "legend": False,
                    "title": f"({next(tags)}) L/D 2.6, inclination {inc:g}°",
                    "layers": [moved_layer(lat, lon, down, dst, marker="o")],
                }
            )
    save(
        panels_figure(
            panels["cylindrical"], ncols=1, title="Fig. 32 (a, b): L/D 2.6 footprint, cylindrical equidistant"
        ),
        FIGURES / "fig32_cylindrical.png",
    )
    save(
        panels_figure(panels["orthographic"], ncols=2, title="Fig. 32 (c, d): L/D 2.6 footprint, orthographic"),
        FIGURES / "fig32_orthographic.png",
    )


def fig33(comparisons):
    panels = []
    for tag, (name, c) in zip("abc", comparisons.items()):
        base, dst = c.nonrotating, c.destination
        pts = base.points
        mlat, mlon = move([p.latitude_deg for p in pts], [p.longitude_deg for p in pts], ORIGIN_EAST, dst)
        alat, alon = approximate_points(base, dst, points=pts)
        layers = [
            footprint_layer(mlat, mlon, reference=dst, label="non-rotating, moved", color="0.55", linewidth=2.2),
            footprint_layer(alat, alon, reference=dst, label="shifted west by ωp t (report)", color="k", marker="o"),
            footprint_layer(
                [p.latitude_deg for p in c.exact.points],
                [p.longitude_deg for p in c.exact.points],
                reference=dst,
                label="flown on the rotating earth",
                color="C3",
                linestyle=(0, (4, 2)),
                marker="s",
            ),
        ]
        panels.append(
            {
                "projection": "cylindrical",
                "extent": "auto",
                "layers": layers,
                "legend": "best",
                "title": f"({tag}) {name}: max error {c.max_error_nmi:.0f} nmi",
            }
        )
    save(
        panels_figure(
            panels,
            ncols=1,
            panel_size=(7.5, 4.2),
            title="Fig. 33: shift due to earth rotation, L/D 1.89 (same inertial entry state)",
        ),
        FIGURES / "fig33_rotation_shift.png",
    )


# ----------------------------------------------------------------------------------------------- table
CASES = {"east (heading 90°)": 90.0, "west (heading −90°)": -90.0, "inclination 60° (heading 30°)": 30.0}


def comparisons(velocity_fps, frames):
    st = study("lod-1.89", velocity_fps)
    spec, settings = st.case.to_spec(), st.to_settings()
    base = fly(st)
    out = {}
    for frame in frames:
        for name, h in CASES.items():
            out[(frame, name)] = approximate_vs_exact(
                spec, settings, Reference(0.0, 0.0, h), velocity_frame=frame, nonrotating=base
            )
    return out


def table(rows: dict, velocity_fps) -> list[str]:
    lines = [
        "| case | exact flight keeps | max error nmi | mean error nmi | move alone, max / mean nmi | "
        "flight time s, non-rotating | flight time s, rotating | down-range extent nmi: non-rot. → shifted → "
        "flown | verdict |",
        "|---|---|---:|---:|---:|---|---|---|---|",
    ]
    for (frame, name), c in rows.items():
        ext = c.downrange_extent_nmi
        verdict = _verdict(ext)
        t0, t1 = c.flight_time_nonrotating_s, c.flight_time_exact_s
        keeps = f"inertial {velocity_fps:,} ft/s" if frame == "inertial" else f"relative {velocity_fps:,} ft/s"
        lines.append(
            f"| {name} | {keeps} | {c.max_error_nmi:,.0f} | {c.mean_error_nmi:,.0f} | "
            f"{c.move_error_nmi['max_nmi']:,.1f} / {c.move_error_nmi['mean_nmi']:,.1f} | "
            f"{t0[0]:,.0f}–{t0[1]:,.0f} | {t1[0]:,.0f}–{t1[1]:,.0f} | "
            f"{ext['nonrotating']:,.0f} → {ext['approximate']:,.0f} → {ext['exact']:,.0f} | {verdict} |"
        )
    return lines


def _verdict(ext):
    def word(a, b):
        return "stretched" if b > a * 1.005 else "compacted" if b < a * 0.995 else "unchanged"

    return f"shift: {word(ext['nonrotating'], ext['approximate'])}; flown: {word(ext['nonrotating'], ext['exact'])}"


def write_doc(main_rows, fast_rows, half189, half26, seconds):
    ee = main_rows[("inertial", "east (heading 90°)")].downrange_extent_nmi
    ew = main_rows[("inertial", "west (heading −90°)")].downrange_extent_nmi
    worst = max(c.max_error_nmi for (f, _), c in main_rows.items() if f == "inertial")
    worst_mean = max(c.mean_error_nmi for (f, _), c in main_rows.items() if f == "inertial")
    doc = f"""# Maps: Section IV of AFWAL-TR-82-3036 (display, moving footprints, earth rotation)

Generated by `python3 scripts/section_iv_figures.py` ({seconds:.0f} s). The geometry is proved in
`tests/core/test_transforms.py` (round trips, geographiclib on a sphere, the report's eqs. 8-15 as printed);
the transform contract is `footprint transform FILE.json` (`footprint.contracts.transform`).

## What is drawn

Maps are plain matplotlib (`footprint.pictures.maps`): cylindrical equidistant and orthographic, a graticule
every 30° (no coastlines: nothing is fetched from outside the project), the footprint boundary joined along
great circles and shaded inside, its points as dots, the initial point as a filled circle with an arrowhead
for the heading, and the ground track of the initial great circle dashed. Lines that would cross longitude
180° are cut there (the report: "the points are not connected when the lines would cross longitude 180°");
the orthographic views are centred on the footprint and hide the far hemisphere.

Footprints: single-parameter (φ_B = Kζ, Section II.6), Table 2 entry (364,800 ft, 24,480 ft/s, γ −2°, east
at 0°, 0°), (L/D)max, stop at 50,000 ft, flown on a **non-rotating** oblate earth as Section IV takes them.
For Figs. 31 and 32 only the left half is flown; the right half is its mirror image (Section IV: "input of
only half of a symmetrical footprint").

| footprint | max down-range nmi | min down-range nmi | max cross-range nmi | flight times s |
|---|---:|---:|---:|---|
{_footprint_row("L/D 1.89 (lod-1.89), non-rotating", half189)}
{_footprint_row("L/D 2.6 (lod-2.6), non-rotating", half26)}

These are smaller than the report's Section II footprints (L/D 1.89: 14,500 nmi, flight times 2,000–4,000 s):
on a non-rotating earth 24,480 ft/s is also the inertial speed, while the report's rotating-earth entry has
26,031 ft/s inertial. The second table below repeats the comparison at 26,031 ft/s.

## Fig. 31: L/D 1.89 footprint moved (re-incline), cylindrical and orthographic

Heading 90° (inclination 0°, as flown), 30° (inclination 60°) and −90° (west); orthographic at inclination
0° and 60°.

![Fig. 31 a-c](figures/fig31_cylindrical.png)

![Fig. 31 d-e](figures/fig31_orthographic.png)

## Fig. 32: L/D 2.6 footprint, inclination 0° and 30°

The footprint reaches {half26.max_downrange_nmi:,.0f} nmi, almost half the circumference (10,807 nmi): at inclination
30° its front crosses longitude 180° and is cut there on the cylindrical map. On the orthographic map it just
fills the visible hemisphere, its initial point over the limb; the report's L/D 2.6 footprint, flown from the
rotating earth's 26,031 ft/s inertial entry, was larger still and "won't fit on half the globe".

![Fig. 32 a-b](figures/fig32_cylindrical.png)

![Fig. 32 c-d](figures/fig32_orthographic.png)

## Fig. 33 and the table: the first-order rotation shift against flying again

The report's approximation (Section IV.3) moves the non-rotating footprint and shifts every point west by
ω_p t (ω_p = 0.004178 deg/s, t its own flight time); the initial point (t = 0) stays. The exact alternative
(`footprint.core.rotation.approximate_vs_exact`) flies the same study again on the rotating earth from the
moved initial point and heading; the two are compared point by point (same bank setting, same side),
distances on the sphere of radius R' = 3,440.07 nmi.

Which entry state the rotating flight keeps is a choice the report leaves open. **Inertial** keeps the
non-rotating flight's inertial speed, flight-path angle and heading: the approximation's own premise (the
trajectory stays put in space, the earth turns under it). **Relative** keeps the earth-relative numbers,
which adds (east) or removes (west) up to ωr = 1,552 ft/s of inertial speed and so changes the flight
itself; no shift of the end points can model that, and the errors show it.

"Move alone" flies the non-rotating footprint at the new geometry and compares it with the moved one: what
moving costs on the oblate earth (zero on the equator by symmetry; at inclination 60° the J2 and J3 terms act
differently along the new track, and geodetic latitudes are moved as if on a sphere).

### Table 2 entry at 24,480 ft/s (the non-rotating footprint of Figs. 31 and 33)

{chr(10).join(table(main_rows, 24_480))}

### The same at 26,031 ft/s (Table 2's inertial speed; "east, inertial" is then the report's rotating case)

{chr(10).join(table(fast_rows, TABLE2_INERTIAL_FPS))}

![Fig. 33](figures/fig33_rotation_shift.png)

Fig. 33 shows the three inertial cases at 24,480 ft/s: grey the non-rotating footprint moved, black the
report's shifted points, red dashed the footprint flown on the rotating earth. The shift moves the long
flights (front) most: 0.004178 deg/s x 2,818 s = 11.8° of longitude at the front, 1.1° at the back.

### Stretching and compaction

The report: the westward shift "has the effect of stretching the footprint when the initial conditions are
heading west on the equator, compacting it when heading east". **Ours does, with the inertial entry state:**
eastbound the down-range extent of the L/D 1.89 footprint goes from {ee["nonrotating"]:,.0f} nmi to
{ee["approximate"]:,.0f} nmi by the shift and to {ee["exact"]:,.0f} nmi when flown on the rotating earth;
westbound it goes from {ew["nonrotating"]:,.0f} to {ew["approximate"]:,.0f} (shift) and {ew["exact"]:,.0f} nmi (flown).
The first-order shift is within {worst:,.0f} nmi of the flown footprint at every point in these cases (mean {worst_mean:,.0f} nmi
or less): {_share(main_rows)} of the footprint's down-range extent.
With the earth-relative entry state kept instead, the eastbound footprint grows rather than shrinks (more
inertial energy at the same relative speed) and the westbound one shrinks: the report's statement describes
the shift, and holds for the flown footprints only in the inertial sense.

## The transform contract

`footprint transform FILE.json [--csv OUT.csv]` (and `footprint.contracts.transform.run` from Python) takes

```json
{{"points": [{{"latitude_deg": 13.18, "longitude_deg": 115.44, "flight_time_s": 2753}},
            {{"latitude_deg": 29.88, "longitude_deg": 58.77, "flight_time_s": 1944}}],
 "from": {{"latitude_deg": 0, "longitude_deg": 0, "heading_deg": 90}},
 "to": {{"latitude_deg": 0, "longitude_deg": -40, "inclination_deg": 60, "ascending": true}},
 "step_downrange_nmi": 500, "mirror": true, "earth_rotation": "approximate"}}
```

and prints the moved points (`latitude_deg`, `longitude_deg`, `flight_time_s`, `downrange_nmi`,
`crossrange_nmi` about the new initial point, `mirrored`) with the new initial point and heading
(`reference`). `mirror` adds the other half (reflected across the `from` great circle) in reverse order;
`"approximate"` needs every point's `flight_time_s`; `"exact"` needs `"study"` (a footprint study) and
returns that footprint flown again on the rotating earth from the destination. A bad field gets one line
naming it and its allowed range, exit status 2. Moving 100,000 points (re-node, re-incline, step and the
shift) takes about 10 ms on one core; `bench/bench_transform.py` compares it with the report's own procedure
(eqs. 8-11 forward, the eqs. 12-15 iteration back), results in `bench/results/transform.json`.
"""
    DOC.parent.mkdir(parents=True, exist_ok=True)
    DOC.write_text(doc)


def _share(rows):
    shares = [c.max_error_nmi / c.downrange_extent_nmi["nonrotating"] for (f, _), c in rows.items() if f == "inertial"]
    return f"{100 * min(shares):.0f}–{100 * max(shares):.0f} %"


def _footprint_row(name, fp):
    return (
        f"| {name} | {fp.max_downrange_nmi:,.0f} | {fp.min_downrange_nmi:,.0f} | {fp.max_crossrange_nmi:,.0f} | "
        f"{_times(fp)} |"
    )


def _times(fp):
    t = [p.flight_time_s for p in fp.points + fp.interior]
    return f"{min(t):,.0f}–{max(t):,.0f}"


def main():
    t0 = time.perf_counter()
    half189 = fly(study("lod-1.89", mirror_half=False))
    half26 = fly(study("lod-2.6", mirror_half=False))
    fig31(half189)
    fig32(half26)
    main_rows = comparisons(24_480, VELOCITY_FRAMES)
    fast_rows = comparisons(TABLE2_INERTIAL_FPS, ("inertial",))
    fig33({name: main_rows[("inertial", name)] for name in CASES})
    write_doc(main_rows, fast_rows, half189, half26, time.perf_counter() - t0)
    for key, c in list(main_rows.items()) + list(fast_rows.items()):
        print(
            f"{key[0]:>8} {key[1]:<32} max {c.max_error_nmi:7.1f} nmi  mean {c.mean_error_nmi:7.1f} nmi  "
            f"extent {c.downrange_extent_nmi}",
            file=sys.stderr,
        )
    print(
        f"wrote {DOC.relative_to(ROOT)} and docs/figures/fig31_*.png, fig32_*.png, fig33_*.png "
        f"in {time.perf_counter() - t0:.1f} s"
    )


if __name__ == "__main__":
    main()

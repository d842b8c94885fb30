"""The `footprint` command. A user's mistake gets one line on stderr and exit status 2, never a traceback."""

import functools
import json
import sys
from contextlib import contextmanager
from pathlib import Path

import typer
from pydantic import ValidationError

from footprint import contracts, parallel
from footprint.contracts.messages import error_line, printable
from footprint.contracts.records import strict_json
from footprint.core.errors import InputError, NoOptimum
from footprint.core.setting import ControlSetting

app = typer.Typer(
    add_completion=False, no_args_is_help=True, help="Landing footprints of lifting entry vehicles (AFWAL-TR-82-3036)."
)


def _fail(message: str) -> None:
    typer.echo(f"error: {printable(message)}", err=True)  # one line, whatever the file's name or keys hold
    raise typer.Exit(2)


def _read_json(path: Path) -> dict:
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        _fail(f"{path}: cannot read ({exc.strerror})")
    except UnicodeDecodeError as exc:  # JSON is UTF-8 (RFC 8259)
        _fail(f"{path}: not UTF-8 text (byte {exc.start}: {exc.reason}); save it as UTF-8")
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        _fail(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})")
    except RecursionError:
        _fail(f"{path}: not a request: nested deeper than Python's JSON reader goes (about 1,000 levels)")
    except ValueError:  # an integer past Python's limit on digits read from text (not a JSONDecodeError)
        _fail(f"{path}: not a request: a number with more than {sys.get_int_max_str_digits():,} digits")
    if not isinstance(data, dict):
        _fail(f"{path}: expected a JSON object")
    return data


def _request(kind: str, path: Path, data=None):
    """The file's request of this kind, parsed once (footprint.contracts); a mistake: one line, exit 2. `data`: the
    file's JSON, already read."""
    data = _read_json(path) if data is None else data
    try:
        return contracts.parse(kind, data)
    except (ValidationError, InputError) as exc:
        _fail(error_line(exc))


def _writable(path: Path | None, option: str) -> None:
    """An output file or folder named on the command line goes into a folder that exists: one line and exit 2
    before any work, never a traceback or folders made where a typo points."""
    if path is not None and not path.resolve().parent.is_dir():
        _fail(f"{option}: the folder {path.parent} does not exist (create it first)")


def _dask_options(workers: int | None, scheduler: str | None, default: int) -> dict:
    """The runner's keywords for --workers N (0: this process) or --scheduler ADDRESS, else `default` workers (0: this
    process); a bad value: one line, exit 2."""
    if workers is not None and not 0 <= workers <= 256:
        _fail(f"--workers: {workers} is outside the allowed range 0 to 256")
    if scheduler is not None and (workers is not None or "://" not in scheduler):
        _fail("--scheduler: give an address like tcp://host:8786 (and no --workers: the scheduler has its own)")
    if scheduler:
        return {"scheduler": scheduler}
    count = default if workers is None else workers
    return {"workers": count} if count else {}


@contextmanager
def _parts_bar(unit: str):
    """A progress bar on stderr over a run's parts, moved by the runner's progress(done, total)."""
    from tqdm import tqdm

    # until the runner says how many parts there are, no count: tqdm's "0analysis [00:00, ?analysis/s]" read as
    # a fault (issue 53 item 12)
    with tqdm(unit=unit, file=sys.stderr, mininterval=0.5, bar_format=f"starting: {unit} [{{elapsed}}]") as bar:

        def progress(done: int, total: int) -> None:
            if bar.total != total:
                bar.total, bar.bar_format = total, None  # tqdm's own bar, with its count, from now on
            bar.update(done - bar.n)

        yield progress


def _answer(result: dict, as_json: bool, lines) -> None:
    """The full JSON when asked or piped (other tools read it); a few lines for a person at a terminal."""
    if as_json or not sys.stdout.isatty():
        typer.echo(strict_json(result, indent=2))
    else:
        typer.echo("\n".join(lines(result)) + "\n(the full result: --json)")


def _reach_lines(r: dict) -> list[str]:
    o, a = r["orbit"], r["analysis"]
    out = [
        f"orbit: inclination {o['inclination_deg']:g} deg, node {o['node_longitude_deg']:g} deg, period "
        f"{o['period_s'] / 60:.1f} min; revolutions {a['revolutions'][0]}-{a['revolutions'][1]}, "
        f"{len(r['windows'])} landing windows, {sum(s['reachable'] for s in r['sites'])} of {len(r['sites'])} "
        "sites reached"
    ]
    for s in r["sites"]:
        if s["reachable"]:
            out.append(
                f"  {s['name']}: {s['windows']} windows on revolutions "
                f"{', '.join(map(str, s['revolutions'][:8]))}{'...' if len(s['revolutions']) > 8 else ''}; "
                f"first deorbit at {s['first_deorbit_time_s'] / 3600:.2f} h"
            )
        else:
            short = (
                ""
                if s["best_margin_nmi"] is None
                else f" (the nearest placement falls {-s['best_margin_nmi']:,.0f} nmi short)"
            )
            out.append(f"  {s['name']}: not reached{short}")
    return out + [f"note: {n}" for n in r.get("notes", [])]


def _optimum_lines(r: dict, payoff: tuple[tuple[str, float], ...] = (), goal: str = "max") -> list[str]:
    """The answer in a few lines; the payoff's value unless it is the cross-range, which the first line gives."""
    s = r["summary"]
    verdict = "optimal" if r.get("feasible") else "NOT feasible"
    cost = (
        f"{r['iterations']} IPOPT iterations, {r['seconds']:.1f} s"
        if r.get("method") == "collocation"
        else f"{r['trajectories']} trajectories, {r['seconds']:.1f} s"
    )
    out = [
        f"{verdict}: cross-range {s['crossrange_nmi']:,.1f} nmi at down-range {s['downrange_nmi']:,.1f} nmi, "
        f"flight {s.get('flight_time_s', float('nan')):,.0f} s ({cost})"
    ]
    value = r.get("objective") if len(payoff) > 1 else s.get(payoff[0][0]) if payoff else None
    if value is not None and payoff != (("crossrange_nmi", 1.0),):
        said = " + ".join(q if w == 1.0 else f"{w:g} x {q}" for q, w in payoff)
        out.append(f"{'maximized' if goal == 'max' else 'minimized'} {said}: {value:,.8g}")
    if r.get("method") == "collocation" and r.get("agreement"):
        g = r["agreement"]
        out.append(f"re-flown by the integrator within {g['end_deg']:.4f} deg")
    if starts := r.get("start_objectives"):
        found = ", ".join("none" if v is None else f"{v:,.8g}" for v in starts)
        out.append(f"the best of {len(starts)} starts, whose first meshes ended at: {found}")
    if inverted := (r.get("refly") or {}).get("inverted_s"):
        out.append(f"flies upside down at negative lift for {inverted:,.0f} s (alpha_bounds_deg can rule it out)")
    if r.get("message") and not r.get("feasible"):
        out.append(r["message"])
    return out


@app.command()
def fly(
    case_file: Path = typer.Argument(..., metavar="CASE.json", help="case file (see README: the case contract)"),
    history: Path | None = typer.Option(None, "--history", metavar="FILE.csv", help="write the time histories"),
):
    """Fly one trajectory and print its summary as JSON."""
    _writable(history, "--history")
    traj = parallel.run("case", _request("case", case_file))
    if history is not None:
        traj.write_csv(history)
    typer.echo(strict_json(traj.summary, indent=2))


@app.command("footprint")
def footprint_(
    study_file: Path = typer.Argument(..., metavar="STUDY.json", help="footprint study (case + method)"),
    plot: Path | None = typer.Option(
        None, "--plot", metavar="FILE.png", help="draw the footprint (PNG or SVG by the suffix)"
    ),
):
    """Fly a landing footprint and print it as JSON (points in boundary order, area, trajectories). Exit status
    1 with one line on stderr when a collocation footprint's first solves end without an optimum."""
    _writable(plot, "--plot")
    study = _request("footprint", study_file)
    try:
        fp = parallel.run("footprint", study)
    except NoOptimum as exc:  # a collocation footprint's first solves
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(1) from None
    if plot is not None:
        from footprint.pictures.figures import save_footprint_plot

        save_footprint_plot(fp, plot)
    typer.echo(strict_json(fp.to_dict(), indent=2))


@app.command()
def sweep(
    sweep_file: Path = typer.Argument(
        ..., metavar="SWEEP.json", help="sweep file: base case, method, vehicles, velocities, angles"
    ),
    out: Path | None = typer.Option(
        None, "--out", metavar="FOLDER", help="where to write points.csv, summary.csv, figures/ [./NAME]"
    ),
    workers: int | None = typer.Option(
        None, "--workers", metavar="N", help="local worker processes [the number of cores]"
    ),
    scheduler: str | None = typer.Option(
        None, "--scheduler", metavar="tcp://HOST:PORT", help="a running Dask scheduler instead of a local cluster"
    ),
):
    """Fly a footprint data base (Appendix C) on Dask, one task per footprint; print the summary table.

    Exit status 1 when some footprints failed (their rows carry the error), 2 for a bad sweep file."""
    from contextlib import ExitStack

    from footprint.parallel import dask_client

    _writable(out, "--out")
    sw = _request("sweep", sweep_file)
    if workers is not None and not 1 <= workers <= 256:
        _fail(f"--workers: {workers} is outside the allowed range 1 to 256")
    if scheduler is not None and (workers is not None or "://" not in scheduler):
        _fail("--scheduler: give an address like tcp://host:8786 (and no --workers: the scheduler has its own)")
    folder = out if out is not None else Path(sw.name)
    with ExitStack() as stack:
        try:
            client = stack.enter_context(dask_client(workers=workers, scheduler=scheduler))
        except OSError as exc:  # no scheduler there
            _fail(f"--scheduler: cannot connect to {scheduler} ({exc})")
        result = parallel.run("sweep", sw, stack.enter_context(_parts_bar("footprint")), client=client)
    written = result.write(folder)
    _print_sweep_summary(result)
    figures = sum(p.suffix in (".png", ".svg") for p in written)
    typer.echo(
        f"{len(result.runs)} footprints, {result.trajectories} trajectories in {result.seconds:.1f} s on "
        f"{result.workers} worker(s); wrote {folder}/points.csv, summary.csv"
        + (f" and {figures} figures" if figures else f" ({result.figures_note})" if result.figures_note else "")
    )
    if result.errors:
        typer.echo(
            f"error: {len(result.errors)} of {len(result.runs)} footprints failed; see the error column "
            f"of {folder}/summary.csv",
            err=True,
        )
        raise typer.Exit(1)


@app.command()
def disperse(
    study_file: Path = typer.Argument(
        ..., metavar="STUDY.json", help="dispersion study: a footprint study, distributions, samples, sites"
    ),
    workers: int | None = typer.Option(
        None, "--workers", metavar="N", help="local worker processes [the cores]; 0: fly in this process"
    ),
    scheduler: str | None = typer.Option(
        None, "--scheduler", metavar="tcp://HOST:PORT", help="a running Dask scheduler instead of a local cluster"
    ),
    figure: Path | None = typer.Option(
        None, "--figure", metavar="FILE.png", help="draw the nominal and confidence footprints, clouds, ellipses"
    ),
    geojson_out: Path | None = typer.Option(
        None, "--geojson", metavar="FILE.geojson", help="the nominal and confidence footprints, ellipses, sites"
    ),
    csv_out: Path | None = typer.Option(
        None, "--csv", metavar="FILE.csv", help="each site's probability and its 95 % interval"
    ),
    clouds: int = typer.Option(
        1_000, "--clouds", metavar="N", min=0, help="landing points of each setting kept in the JSON"
    ),
    as_json: bool = typer.Option(False, "--json", help="print the full JSON (the default when piped)"),
):
    """Fly a footprint study in N Monte Carlo samples of its entry, air and aerodynamics (one Dask task per chunk
    of samples): each setting's landing cloud, mean, covariance and 1/3-sigma ellipses, the footprint reached with
    probability p, each site's probability with its 95 % interval, and every flight that did not land, counted.
    A study with a guided case instead of a footprint ({"case": ..., "radius_nmi": [...]}) flies every sample with
    its entry guidance, and open loop beside it: the miss distances, CEP, P(within R) and the spreads."""
    from contextlib import ExitStack

    for path, option in ((figure, "--figure"), (geojson_out, "--geojson"), (csv_out, "--csv")):
        _writable(path, option)
    data = _read_json(study_file)
    if isinstance(data, dict) and "case" in data and "footprint" not in data:
        return _guided_disperse(study_file, data, workers, scheduler, figure, geojson_out, csv_out, clouds, as_json)
    study = _request("dispersion", study_file, data)
    dask = _dask_options(workers, scheduler, parallel.default_workers())
    with ExitStack() as stack:
        progress = stack.enter_context(_parts_bar("chunk"))
        try:
            stats, info = parallel.run("dispersion", study, progress, **dask)
        except OSError as exc:  # no scheduler there
            _fail(f"--scheduler: cannot connect to {scheduler} ({exc})")
    if figure is not None:
        from footprint.pictures.figures import dispersion_figure, save

        save(dispersion_figure(stats), figure)
    dispersion = contracts.module("dispersion")
    result = dispersion.to_dict(study, stats, clouds, info)
    if geojson_out is not None:
        from footprint.pictures.geojson import dispersion_collection

        geojson_out.write_text(strict_json(dispersion_collection(result)))
    if csv_out is not None:
        csv_out.write_text(dispersion.sites_csv(result))
    _answer(result, as_json, _dispersion_lines)


def _guided_disperse(study_file, data, workers, scheduler, figure, geojson_out, csv_out, clouds, as_json) -> None:
    from contextlib import ExitStack

    study = _request("guided_dispersion", study_file, data)
    dask = _dask_options(workers, scheduler, parallel.default_workers())
    with ExitStack() as stack:
        progress = stack.enter_context(_parts_bar("chunk"))
        try:
            stats, info = parallel.run("guided_dispersion", study, progress, **dask)
        except OSError as exc:
            _fail(f"--scheduler: cannot connect to {scheduler} ({exc})")
    kind = contracts.module("guided_dispersion")
    result = kind.to_dict(study, stats, clouds, info)
    if figure is not None:
        from footprint.pictures.figures import guided_dispersion_figure, save

        save(guided_dispersion_figure(result), figure)
    if geojson_out is not None:
        from footprint.pictures.geojson import guided_dispersion_collection

        geojson_out.write_text(strict_json(guided_dispersion_collection(result)))
    if csv_out is not None:
        csv_out.write_text(kind.within_csv(result))
    _answer(result, as_json, _guided_dispersion_lines)


@app.command("guided-footprint")
def guided_footprint(
    study_file: Path = typer.Argument(
        ..., metavar="STUDY.json", help="a guided case, its dispersions, rays, samples, R and p"
    ),
    workers: int | None = typer.Option(
        None, "--workers", metavar="N", help="local worker processes [the cores]; 0: fly in this process"
    ),
    scheduler: str | None = typer.Option(
        None, "--scheduler", metavar="tcp://HOST:PORT", help="a running Dask scheduler instead of a local cluster"
    ),
    figure: Path | None = typer.Option(
        None, "--figure", metavar="FILE.png", help="draw the guided footprint inside the report's and the optimal"
    ),
    geojson_out: Path | None = typer.Option(
        None, "--geojson", metavar="FILE.geojson", help="the guided, undispersed guided, report's and optimal rings"
    ),
    as_json: bool = typer.Option(False, "--json", help="print the full JSON (the default when piped)"),
):
    """Trace the guided footprint: the targets the guided vehicle reaches within R nmi in at least p of the dispersed
    samples, one Dask task per ray from a centre on the initial great circle, beside the report's footprint and the
    true optimal one of the same vehicle flown to the same end; the guidance's margin to each, in nmi² and percent."""
    from contextlib import ExitStack

    for path, option in ((figure, "--figure"), (geojson_out, "--geojson")):
        _writable(path, option)
    study = _request("guided_footprint", study_file)
    dask = _dask_options(workers, scheduler, parallel.default_workers())
    with ExitStack() as stack:
        progress = stack.enter_context(_parts_bar("ray"))
        try:
            result = parallel.run("guided_footprint", study, progress, **dask)
        except OSError as exc:
            _fail(f"--scheduler: cannot connect to {scheduler} ({exc})")
    if figure is not None:
        from footprint.pictures.figures import guided_footprint_figure, save

        save(guided_footprint_figure(result), figure)
    if geojson_out is not None:
        from footprint.pictures.geojson import guided_footprint_collection

        geojson_out.write_text(strict_json(guided_footprint_collection(result)))
    _answer(result, as_json, _guided_footprint_lines)


def _guided_footprint_lines(r: dict) -> list[str]:
    run, st = r["run"], r["settings"]
    where = f"on {run['workers']} worker(s)" if run["workers"] else "in this process"
    out = [
        f"{st['rays']} rays, {st['samples']:,} samples a target, within {st['radius_nmi']:g} nmi in "
        f"{st['probability']:.0%}: {r['flights']:,} guided flights in {run['seconds']:.1f} s {where}",
        f"  {'footprint':<16} {'area nmi²':>12} {'margin nmi²':>12} {'margin':>7}  inside at every ray",
    ]
    for name in ("guided", "nominal_guided", "report", "optimal"):
        ring = r.get(name)
        if ring is None:
            continue
        m = r.get(f"margin_to_{name}")
        tail = (
            f" {m['area_nmi2']:>12,.0f} {m['percent']:>6.1f}%  {'yes' if m['inside_at_every_ray'] else 'NO'}"
            if m
            else ""
        )
        out.append(f"  {name:<16} {ring['area_nmi2']:>12,.0f}{tail}")
    return out


def _guided_dispersion_lines(r: dict) -> list[str]:
    run, t = r["run"], r["target"]
    where = f"on {run['workers']} worker(s)" if run["workers"] else "in this process"
    out = [
        f"{r['samples']:,} samples ({r['design']}, seed {r['seed']}) in {run['seconds']:.1f} s {where}; target "
        f"{t['latitude_deg']:.3f}, {t['longitude_deg']:.3f} ({t['downrange_nmi']:,.0f} nmi down-range, "
        f"{t['crossrange_nmi']:,.0f} cross-range); misses of the terminal-area interface circle "
        f"{t.get('interface_range_nmi', 0.0):g} nmi about it; nominal guided miss "
        f"{r['nominal']['guidance']['miss_nmi']:.2f} nmi"
    ]
    radii = [w["radius_nmi"] for w in r["guided"]["within"]]
    out.append(
        f"  {'':<10} {'landed':>7} {'mean nmi':>9} {'CEP':>8} {'p99':>8}"
        + "".join(f" {f'P<={x:g}':>16}" for x in radii)
    )
    for mode in ("guided", "open_loop"):
        if mode not in r:
            continue
        m, miss = r[mode], r[mode]["miss_nmi"] or {}
        cells = "".join(
            f" {w['probability']:>6.3f} ({w['interval'][0]:.2f}-{w['interval'][1]:.2f})" for w in m["within"]
        )
        mean, cep, p99 = (miss.get(k, float("nan")) for k in ("mean", "cep", "p99"))
        out.append(f"  {mode:<10} {m['landed']:>7,} {mean:>9.2f} {cep:>8.2f} {p99:>8.2f}{cells}")
        notes = [f"{m[k]:,} {what}" for k, what in (("saturated_samples", "saturated the bank"),
                 ("limit_bound_samples", "bound by a path limit")) if m.get(k)]  # fmt: skip
        notes += [f"{v:,} exceeded {k}" for k, v in m["violations"].items() if v]
        if notes:
            out.append("    " + "; ".join(notes))
    return out


def _dispersion_lines(r: dict) -> list[str]:
    o, run = r["outcomes"], r["run"]
    ended = ", ".join(f"{v:,} {k}" for k, v in o.items() if k not in ("flights", "landed"))
    where = f"on {run['workers']} worker(s)" if run["workers"] else "in this process"
    out = [
        f"{r['samples']:,} samples ({r['design']}, seed {r['seed']}): {o['flights']:,} trajectories in "
        f"{run['seconds']:.1f} s {where}; "
        f"{o.get('landed', 0):,} landed" + (f", {ended}" if ended else "")
    ]
    out.append(f"  {'setting':<28} {'landed':>7} {'mean D nmi':>10} {'mean X nmi':>10} {'sd D':>7} {'sd X':>7}")
    for f in r["flights"]:
        name = f"{f['side']} {ControlSetting.of(f['parameter']).words()}"
        if "covariance_nmi2" in f:
            (a, _), (_, d) = f["covariance_nmi2"]
            out.append(
                f"  {name:<28} {f['landed']:>7,} {f['mean_downrange_nmi']:>10,.0f} "
                f"{f['mean_crossrange_nmi']:>10,.0f} {a**0.5:>7.1f} {d**0.5:>7.1f}"
            )
        else:
            out.append(f"  {name:<28} {f['landed']:>7,}")
        for what, samples in f["outcome_samples"].items():
            listed = ", ".join(map(str, samples)) + (", ..." if f["outcomes"][what] > len(samples) else "")
            out.append(f"    {f['outcomes'][what]:,} {what}: samples {listed}")
    for c in r["confidence"]:
        area = sum(ring["area_nmi2"] for ring in c["rings"])
        out.append(
            f"  footprint reached with probability >= {c['level']:g}: {area:,.0f} nmi2 in {len(c['rings'])} ring(s)"
        )
    if r["histories"]:
        asked = sorted({h["sample"] for h in r["histories"]})
        out.append(f"  the flights of sample(s) {', '.join(map(str, asked))} with their histories: in the JSON")
    for s in r["sites"]:
        lo, hi = s["interval"]
        out.append(
            f"  {s['name']}: probability {s['probability']:.3f} ({s['interval_level']:.0%} interval "
            f"{lo:.3f}-{hi:.3f}); {'inside' if s['inside_nominal'] else 'outside'} the nominal footprint"
        )
    return out


def _print_sweep_summary(result):
    def num(v, fmt):
        return format(v, fmt) if v is not None else "-".rjust(int(fmt.split(".")[0]))

    typer.echo(
        f"{'vehicle':<16} {'V fps':>7} {'gamma':>6} {'max X nmi':>9} {'max D nmi':>9} {'min D nmi':>9} "
        f"{'area nmi2':>10} {'traj':>5} {'s':>6}  note"
    )
    for r in result.summary_rows():
        note = r["error"] or ", ".join(
            f"{r[k]} {what}"
            for k, what in (("skip_outs", "skipped out"), ("unfinished", "unfinished (max_steps)"))
            if r.get(k)
        )
        typer.echo(
            f"{r['vehicle']:<16} {r['entry_velocity_fps']:>7.0f} {r['entry_gamma_deg']:>6g} "
            f"{num(r.get('max_crossrange_nmi'), '9.0f')} {num(r.get('max_downrange_nmi'), '9.0f')} "
            f"{num(r.get('min_downrange_nmi'), '9.0f')} {num(r.get('area_nmi2'), '10.3g')} "
            f"{r['trajectories']:>5} {r['seconds']:>6.2f}  {note}"
        )


@app.command()
def transform(
    request_file: Path = typer.Argument(
        ..., metavar="FILE.json", help="transform request: points, from, to, step, mirror, rotation"
    ),
    csv_out: Path | None = typer.Option(None, "--csv", metavar="OUT.csv", help="also write the points as CSV"),
):
    """Move footprint points to another node, inclination or deorbit point (Section IV), mirror a half, and
    allow for the earth's rotation; print the moved points as JSON."""
    from footprint.contracts.transform import write_csv

    _writable(csv_out, "--csv")
    request = _request("transform", request_file)
    try:
        result = parallel.run("transform", request)
    except InputError as exc:  # a place the request's numbers cannot make (an inclination the latitude cannot fly)
        _fail(error_line(exc))
    if csv_out is not None:
        write_csv(result, csv_out)
    typer.echo(strict_json(result, indent=2))


@app.command()
def reach(
    request_file: Path = typer.Argument(
        ..., metavar="REACH.json", help="reach request: footprint, orbit, sites, revolutions"
    ),
    csv_out: Path | None = typer.Option(None, "--csv", metavar="FILE.csv", help="also write the windows as CSV"),
    as_json: bool = typer.Option(False, "--json", help="print the full JSON (the default when piped)"),
):
    """Which landing sites a footprint reaches from which deorbit points of which revolutions (Section IV).

    Prints JSON: the orbit, the footprint, a summary per site and the windows (contiguous runs of deorbit
    argument of latitude per revolution and site); on a terminal, a short summary unless --json."""
    from footprint.contracts.reach import write_windows_csv

    _writable(csv_out, "--csv")
    result = parallel.run("reach", _request("reach", request_file))
    if csv_out is not None:
        write_windows_csv(result, csv_out)
    _answer(result, as_json, _reach_lines)


@app.command()
def opportunities(
    study_file: Path = typer.Argument(
        ..., metavar="STUDY.json", help="a TLE, a UTC window, sites, the deorbit burn and a footprint study"
    ),
    workers: int | None = typer.Option(
        None, "--workers", metavar="N", help="local worker processes [the cores]; 0: fly in this process"
    ),
    scheduler: str | None = typer.Option(
        None, "--scheduler", metavar="tcp://HOST:PORT", help="a running Dask scheduler instead of a local cluster"
    ),
    csv_out: Path | None = typer.Option(None, "--csv", metavar="FILE.csv", help="also write the opportunities as CSV"),
    ics_out: Path | None = typer.Option(
        None, "--ics", metavar="FILE.ics", help="also write the opportunities that meet the rules as an iCalendar"
    ),
    geojson_out: Path | None = typer.Option(
        None, "--geojson", metavar="FILE.geojson", help="the ground tracks, deorbit arcs, entries and footprints"
    ),
    figure: Path | None = typer.Option(
        None, "--figure", metavar="FILE.png", help="the opportunities on a UTC timeline, night at each site shaded"
    ),
    oem_out: Path | None = typer.Option(
        None, "--oem", metavar="FILE.oem", help="the chosen opportunity's coast (TEME) and entry (GRC) as a CCSDS OEM"
    ),
    czml_out: Path | None = typer.Option(
        None, "--czml", metavar="FILE.czml", help="the chosen opportunity's coast and entry as CZML for Cesium"
    ),
    chosen: int = typer.Option(
        0,
        "--opportunity",
        min=0,
        metavar="N",
        help="the opportunity --oem and --czml write: its index in landing order",
    ),
    as_json: bool = typer.Option(False, "--json", help="print the full JSON (the default when piped)"),
):
    """Landing opportunities in UTC: for each revolution of the window and each site, the deorbit burns (time, Δv)
    whose coast and entry put the site inside the footprint flown from that entry, with the landing time, the
    margin and the sun at the site; one Dask task per revolution."""
    from contextlib import ExitStack

    outputs = ((csv_out, "--csv"), (ics_out, "--ics"), (geojson_out, "--geojson"), (figure, "--figure"))
    for path, option in (*outputs, (oem_out, "--oem"), (czml_out, "--czml")):
        _writable(path, option)
    study = _request("opportunities", study_file)
    dask = _dask_options(workers, scheduler, parallel.default_workers())
    with ExitStack() as stack:
        progress = stack.enter_context(_parts_bar("revolution"))
        try:
            result = parallel.run("opportunities", study, progress, **dask)
        except OSError as exc:
            _fail(f"--scheduler: cannot connect to {scheduler} ({exc})")
        except InputError as exc:
            _fail(error_line(exc))
    kind = contracts.module("opportunities")
    if csv_out is not None:
        csv_out.write_text(kind.opportunities_csv(result))
    if ics_out is not None:
        ics_out.write_text(kind.opportunities_ics(result), newline="")
    if geojson_out is not None:
        from footprint.pictures.geojson import opportunities_collection

        geojson_out.write_text(strict_json(opportunities_collection(result)))
    if figure is not None:
        from footprint.pictures.figures import opportunities_timeline_figure, save

        save(opportunities_timeline_figure(result), figure)
    _write_opportunity_files(study, result, chosen, oem_out, czml_out)
    _answer(result, as_json, _opportunities_lines)


def _write_opportunity_files(study, result: dict, index: int, oem_out: Path | None, czml_out: Path | None) -> None:
    """--oem and --czml of the opportunity at --opportunity (one line naming the option when it is not there)."""
    from footprint.contracts import opportunity_files

    if oem_out is None and czml_out is None:
        return
    try:
        opportunity_files.opportunity_at(result, index)
    except InputError as exc:
        _fail(f"--opportunity: {exc.message}")
    if oem_out is not None:
        oem_out.write_text(opportunity_files.opportunity_oem(study, result, index))
    if czml_out is not None:
        czml_out.write_text(opportunity_files.opportunity_czml(study, result, index))


def _opportunities_lines(r: dict) -> list[str]:
    e, run = r["elements"], r["run"]
    where = f"on {run['workers']} worker(s)" if run["workers"] else "in this process"
    out = [
        f"{e['name'] or e['satellite_number']}: {e['inclination_deg']:.2f} deg, {e['period_min']:.1f} min; "
        f"{r['window']['start_utc']} to {r['window']['end_utc']}, {len(r['ascending_nodes_utc'])} ascending nodes; "
        f"{len(r['opportunities'])} opportunities and {len(r['near_misses'])} near misses in {run['seconds']:.1f} s "
        f"{where}",
        f"  {'site':<36} {'found':>5} {'taken':>5} {'near':>5}  {'first landing (UTC)':<24} {'best margin':>11}",
    ]
    for s in r["sites"]:
        best = "-" if s["best_margin_nmi"] is None else f"{s['best_margin_nmi']:,.0f} nmi"
        out.append(
            f"  {s['name'][:36]:<36} {s['opportunities']:>5} {s['meeting_rules']:>5} {s['near_misses']:>5}  "
            f"{s['first_landing_utc'] or '-':<24} {best:>11}"
        )
    return out


@app.command()
def optimize(
    study_file: Path = typer.Argument(..., metavar="STUDY.json", help="optimization study (DESIGN.md)"),
    plot: Path | None = typer.Option(
        None, "--plot", metavar="FILE.png", help="draw the convergence history and the bank schedule"
    ),
    as_json: bool = typer.Option(False, "--json", help="print the full JSON (the default when piped)"),
):
    """Optimize the bank schedule (creep + pattern, Section II.4) or, with "method": "collocation", alpha(t) and
    bank(t) to the true optimum (IPOPT): prints the optimum, its parameters or control tables and the convergence
    history as JSON. Exit status 1 when no feasible point was found (the result, and for the collocation one line
    on stderr, say by how much). On a terminal, a short summary unless --json."""
    _writable(plot, "--plot")
    study = _request("optimize", study_file)
    result = parallel.run("optimize", study)
    if plot is not None:
        from footprint.pictures.figures import collocation_figure, optimization_figure, save

        save((collocation_figure if study.method == "collocation" else optimization_figure)(result), plot)
    _answer(
        result.to_dict(),
        as_json,
        functools.partial(_optimum_lines, payoff=study.payoff.objective(), goal=study.payoff.goal),
    )
    if study.method == "collocation" and not result.feasible:
        typer.echo(f"error: {result.one_line()}", err=True)
    if not result.feasible:
        raise typer.Exit(1)


@app.command("run")
def run_(
    kind: str = typer.Argument(
        ...,
        metavar="KIND",
        help="a kind of job (footprint, optimize, sweep, reach, dispersion, or one a contract module adds)",
    ),
    request_file: Path = typer.Argument(..., metavar="REQUEST.json", help="the request, as a job's study"),
    workers: int | None = typer.Option(
        None, "--workers", metavar="N", help="local worker processes [0: fly in this process]"
    ),
    scheduler: str | None = typer.Option(
        None, "--scheduler", metavar="tcp://HOST:PORT", help="a running Dask scheduler instead of a local cluster"
    ),
    as_json: bool = typer.Option(False, "--json", help="print the full JSON (the default when piped)"),
):
    """Run any kind of job with the one runner, as the service's job engine does, and print what its job stores:
    {"result": ..., "footprints": [...]} as JSON when piped or with --json, a short summary on a terminal. A
    progress bar over its parts on stderr."""

    kinds = contracts.job_kinds()
    if kind not in kinds:
        _fail(f"KIND: {kind!r} is not a kind of job; allowed: {', '.join(kinds)}")
    request = _request(kind, request_file)
    dask = _dask_options(workers, scheduler, 0)
    work = contracts.module(kind).WORK
    with _parts_bar(work.part_unit) as progress:
        try:
            answer = parallel.run(kind, request, progress, **dask)
        except OSError as exc:  # no scheduler there
            _fail(f"--scheduler: cannot connect to {scheduler} ({exc})")
    try:
        stored = work.store(request, answer, None)
    except NoOptimum as exc:  # what fails the job fails the command
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(1) from None
    _answer({"result": stored.result, "footprints": stored.footprints}, as_json, functools.partial(_stored_lines, kind))


def _stored_lines(kind: str, stored: dict) -> list[str]:
    """What a job stored, in a few lines: the kind's own summary where the CLI has one, else what the result holds."""
    result, footprints = stored["result"], stored["footprints"]
    said = {"reach": _reach_lines, "optimization": _optimum_lines, "dispersion": _dispersion_lines}
    out: list[str] = []
    for key, value in result.items():
        if key in said and isinstance(value, dict):
            out += said[key](value)
        elif isinstance(value, (list, dict)):
            out.append(f"{key}: {len(value):,} {'items' if isinstance(value, list) else 'entries'}")
        else:
            out.append(f"{key}: {value}")
    for fp in footprints:
        out.append(
            f"footprint {fp['name']}: max cross-range {fp['max_crossrange_nmi']:,.0f} nmi, down-range "
            f"{fp['min_downrange_nmi']:,.0f}-{fp['max_downrange_nmi']:,.0f} nmi, {fp['trajectories']:,} trajectories"
        )
    return out or [f"{kind}: done"]


@app.command("map")
def map_(
    footprint_file: Path = typer.Argument(
        ..., metavar="FOOTPRINT.json", help="a footprint as `footprint footprint` prints it"
    ),
    out: Path = typer.Option(Path("map.html"), "-o", "--out", metavar="MAP.html", help="the HTML file to write"),
    title: str | None = typer.Option(None, "--title", help="the map's title [vehicle and method]"),
):
    """Write a standalone HTML map of a footprint (folium, cylindrical equidistant, Natural Earth) that works
    offline: Leaflet and the coastlines are inlined, nothing is loaded from the internet."""
    from footprint.pictures.folium_page import write_footprint_map

    _writable(out, "--out")
    data = _read_json(footprint_file)
    try:
        write_footprint_map(data, out, title)
    except (ValidationError, InputError) as exc:  # not a footprint (or Leaflet not installed)
        _fail(error_line(exc))
    typer.echo(f"wrote {out}")


@app.command()
def serve(
    host: str | None = typer.Option(None, "--host", help="address to listen on [FOOTPRINT_HOST or 127.0.0.1]"),
    port: int | None = typer.Option(None, "--port", help="port [FOOTPRINT_PORT or 8000]"),
    database_url: str | None = typer.Option(
        None, "--database-url", metavar="URL", help="[FOOTPRINT_DATABASE_URL or sqlite:///footprint.db]"
    ),
    workers: int | None = typer.Option(
        None, "--workers", metavar="N", help="local Dask worker processes [FOOTPRINT_DASK_WORKERS or the cores]"
    ),
    api_processes: int | None = typer.Option(
        None,
        "--api-processes",
        metavar="N",
        help="processes answering HTTP over the one database; past 1 this one runs the jobs "
        "[FOOTPRINT_API_PROCESSES or 1]",
    ),
):
    """Run the web service and the map page (SQLite in the working directory and a local Dask cluster unless
    FOOTPRINT_* settings say otherwise); the API is under /api, its docs at /docs."""
    from footprint.service.processes import serve as run_service
    from footprint.service.settings import load_settings

    try:
        settings = load_settings(
            host=host, port=port, database_url=database_url, dask_workers=workers, api_processes=api_processes
        )
    except ValidationError as exc:
        _fail(error_line(exc))
    base = f"http://{settings.host}:{settings.port}"
    _say_service_progress().info(
        "the map page at %s/, the API under %s/api, its docs at %s/docs and %s/redoc (database %s); until it is "
        "ready, %s/api/health says 'starting' and the step under way",
        *[base] * 4,
        settings.database_url.split("://")[0],
        base,
    )
    run_service(settings)


def _say_service_progress():
    """The service's start-up steps and its jobs' ends on stderr, "12:04:31Z footprint: ..." (uvicorn configures only
    its own loggers: without a handler these INFO lines were dropped, and a first start compiling for a minute said
    nothing; without the time a slow start could not be told from a stuck one). The logger."""
    import logging
    import time

    handler = logging.StreamHandler(sys.stderr)
    stamped = logging.Formatter("%(asctime)s footprint: %(message)s", datefmt="%H:%M:%SZ")
    stamped.converter = time.gmtime  # UTC, as the "Z" says
    handler.setFormatter(stamped)
    logger = logging.getLogger("footprint")
    logger.addHandler(handler)
    logger.setLevel(logging.INFO)
    return logger


@app.command()
def vehicles(as_json: bool = typer.Option(False, "--json", help="print JSON instead of a table")):
    """List the built-in vehicles with (L/D)max at Mach 20 and 200,000 ft beside the report's value."""
    from footprint.core.aero import vehicle_summaries

    rows = vehicle_summaries()
    if as_json:
        typer.echo(strict_json(rows, indent=2))
        return
    typer.echo(f"{'id':<10} {'W/S psf':>8} {'(L/D)max':>9} {'alpha deg':>9} {'report':>7}  note")
    for r in rows:
        rep = "-" if r["reported_ld_max"] is None else f"{r['reported_ld_max']:.2f}"
        typer.echo(
            f"{r['id']:<10} {r['wing_loading_psf']:>8.0f} {r['ld_max_m20_200kft']:>9.3f} "
            f"{r['alpha_ld_max_deg']:>9.2f} {rep:>7}  {r.get('note', '')}"
        )


def main():
    try:
        app()
    except InputError as exc:  # a user's mistake found deeper in the core
        typer.echo(f"error: {error_line(exc)}", err=True)
        sys.exit(2)


if __name__ == "__main__":
    main()

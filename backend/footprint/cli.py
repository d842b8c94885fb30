"""The `footprint` command. A user's mistake gets one line on stderr and exit status 2, never a traceback."""

import json
import sys
from pathlib import Path
from typing import Optional

import typer
from pydantic import ValidationError

from footprint.cases import error_line, parse_case
from footprint.core.errors import InputError

app = typer.Typer(add_completion=False, no_args_is_help=True,
                  help="Landing footprints of lifting entry vehicles (AFWAL-TR-82-3036).")


def _fail(message: str) -> None:
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(2)


def _read_json(path: Path) -> dict:
    try:
        text = path.read_text()
    except OSError as exc:
        _fail(f"{path}: cannot read ({exc.strerror})")
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        _fail(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})")
    if not isinstance(data, dict):
        _fail(f"{path}: expected a JSON object")
    return data


def _json_default(o):
    return float(o) if hasattr(o, "__float__") else str(o)


@app.command()
def fly(case_file: Path = typer.Argument(..., metavar="CASE.json", help="case file (see README: the case contract)"),
        history: Optional[Path] = typer.Option(None, "--history", metavar="FILE.csv", help="write the time histories")):
    """Fly one trajectory and print its summary as JSON."""
    from footprint.core.trajectory import simulate

    data = _read_json(case_file)
    try:
        spec = parse_case(data).to_spec()
    except (ValidationError, InputError) as exc:
        _fail(error_line(exc))
    traj = simulate(spec)
    if history is not None:
        traj.write_csv(history)
    typer.echo(json.dumps(traj.summary, indent=2, default=_json_default))


@app.command()
def vehicles(as_json: bool = typer.Option(False, "--json", help="print JSON instead of a table")):
    """List the built-in vehicles with (L/D)max at Mach 20 and 200,000 ft beside the report's value."""
    from footprint.core.aero import vehicle_summaries

    rows = vehicle_summaries()
    if as_json:
        typer.echo(json.dumps(rows, indent=2, default=_json_default))
        return
    typer.echo(f"{'id':<10} {'W/S psf':>8} {'(L/D)max':>9} {'alpha deg':>9} {'report':>7}  note")
    for r in rows:
        rep = "-" if r["reported_ld_max"] is None else f"{r['reported_ld_max']:.2f}"
        typer.echo(f"{r['id']:<10} {r['wing_loading_psf']:>8.0f} {r['ld_max_m20_200kft']:>9.3f} "
                   f"{r['alpha_ld_max_deg']:>9.2f} {rep:>7}  {r.get('note', '')}")


def main():
    try:
        app()
    except InputError as exc:  # a user's mistake found deeper in the core
        typer.echo(f"error: {exc}", err=True)
        sys.exit(2)


if __name__ == "__main__":
    main()

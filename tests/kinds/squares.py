"""A toy kind of work, registered only by the tests (tests/test_new_kind.py): the sum of the squares 1..n in
`parts` parts, each part taking `seconds_per_part` in small steps that report progress and honour a stop. It is
the whole of what a new kind needs: a request model, parse_request and WORK."""

import time

from pydantic import BaseModel, ConfigDict, Field

from footprint.contracts.work import RunInfo, Stored, Work

STEP_S = 0.02  # a part's sleep between two progress reports


class Squares(BaseModel):
    model_config = ConfigDict(extra="forbid")

    n: int = Field(ge=1, le=10_000_000)
    parts: int = Field(default=4, ge=1, le=100)
    seconds_per_part: float = Field(default=0.0, ge=0.0, le=600.0)


REQUEST = Squares


def parse_request(data, ctx: dict | None = None) -> Squares:
    return data if isinstance(data, Squares) else Squares.model_validate(data, context=ctx)


def split(request: Squares) -> list[tuple[int, int]]:
    """[first, end) ranges of the integers 1..n, one a part."""
    size = -(-request.n // request.parts)
    return [(a, min(a + size, request.n + 1)) for a in range(1, request.n + 1, size)]


def run_part(request: Squares, part: tuple[int, int], on_progress=None) -> int | None:
    """The sum of the squares in [first, end), after seconds_per_part of steps; None when told to stop."""
    first, end = part
    steps = max(1, round(request.seconds_per_part / STEP_S))
    for step in range(steps):
        if on_progress is not None and on_progress(step / steps, f"range {first}-{end - 1}: step {step} of {steps}"):
            return None
        time.sleep(request.seconds_per_part / steps)
    return sum(k * k for k in range(first, end))


def combine(request: Squares, outputs: list[int], info: RunInfo) -> dict:
    return {"sum": sum(outputs), "parts": info.tasks}


def store(request: Squares, answer: dict, name: str | None) -> Stored:
    return Stored(result={"squares": answer})


WORK = Work(split=split, run_part=run_part, combine=combine, store=store, part_unit="range")

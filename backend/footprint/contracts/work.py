"""How a kind's work runs, as its contract module says it in one `WORK`: the parts it splits into, one part run (in
this process or in a Dask worker, which parses the request once), the parts' outputs combined into the kind's answer,
and, for a kind the service runs as a job, that answer as the rows the job store writes. footprint.parallel is the
one runner of every kind; it calls only these."""

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

# on_progress(fraction of the part done, note) -> True to stop: the core's long loops take it (a cancel, a time limit)
OnProgress = Callable[[float, str], bool | None]


def stop_question(on_progress: OnProgress | None, note: str, fraction: float = 0.0) -> Callable[[], bool] | None:
    """The core's question before each flight and guidance prediction (FlightSpec.stop_asked) from a part's
    on_progress, asked at `fraction` of the part with `note`: True stops the flight (errors.Stopped)."""
    if on_progress is None:
        return None
    return lambda: bool(on_progress(fraction, note))


@dataclass(frozen=True)
class RunInfo:
    """How a run went: its tasks, the workers it had (0: this process), and its seconds (first part submitted to last
    output; before them, starting or reaching the cluster and warming numba in this process)."""

    tasks: int
    workers: int = 0
    seconds: float = 0.0
    startup_seconds: float = 0.0
    warm_seconds: float = 0.0


@dataclass(frozen=True)
class Stored:
    """A job's answer as the store keeps it: the result document (JSON-ready) and the footprint records it made."""

    result: dict[str, Any]
    footprints: list[dict[str, Any]] = field(default_factory=list)


def _one_part(request: Any) -> Sequence[None]:
    return (None,)


def _only_output(request: Any, outputs: list[Any], info: RunInfo) -> Any:
    return outputs[0]


def _no_name(request: Any) -> str | None:
    return None


@dataclass(frozen=True)
class Work:
    """A kind's work. `run_part` must be a module-level function (a Dask task pickles it by name); parts are plain,
    small data. `store` is None for a kind the service answers at once (no job); `part_unit` names a part on a
    progress bar."""

    run_part: Callable[[Any, Any, OnProgress | None], Any]  # (request, part, on_progress) -> the part's output
    split: Callable[[Any], Sequence[Any]] = _one_part  # request -> its parts
    combine: Callable[[Any, list[Any], RunInfo], Any] = _only_output  # (request, outputs, info) -> the answer
    store: Callable[[Any, Any, str | None], Stored] | None = None  # (request, answer, job name) -> the job's rows
    default_name: Callable[[Any], str | None] = _no_name  # a job's name when none is given
    part_unit: str = "task"


P = TypeVar("P")


class PerStudy(Generic[P]):
    """What every part of one study needs (its spec, its samples...), made once in this process: `make(study)` for a
    study not seen last. One study at a time, as a worker flies one run's parts."""

    def __init__(self, make: Callable[[Any], P]) -> None:
        self._make = make
        self._kept: tuple[Any, P] | None = None

    def __call__(self, study: Any) -> P:
        if self._kept is None or self._kept[0] is not study:
            self._kept = (study, self._make(study))
        return self._kept[1]

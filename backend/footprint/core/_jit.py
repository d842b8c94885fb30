"""All numba settings in one place.

Set FOOTPRINT_NO_JIT=1 to run the same kernels as plain Python (slow; for debugging and coverage).
Compiled functions are cached on disk so that a new process starts in well under a second once the cache
is warm. numba keys a cached function on its own file only, not on the files of the functions it calls
and inlines; so the cache lives in a folder named for a hash of every core source file, and any edit to
the core starts a fresh one ($XDG_CACHE_HOME/footprint, or NUMBA_CACHE_DIR when set). Modules that import
CasADi or the collocation (the transcription, the collocation footprint) hold no compiled code and no constant
that compiled code reads, so they are left out of the hash.
"""

import hashlib
import itertools
import os
import re
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar, overload

NO_JIT = os.environ.get("FOOTPRINT_NO_JIT", "") not in ("", "0")
# No fast-math: IEEE arithmetic, so that a kernel rounds the same wherever it was compiled. LLVM applies "contract"
# (fused multiply-add) and "arcp" (reciprocals) to what it sees after inlining, and a caller compiled in a process that
# loaded its callees from the disk cache inlines nothing of them: with either flag, a cold cache and a warm one gave
# different bits (a dispersion's DOP853 samples flown in this process and on workers that loaded the cache, 44 of 240
# apart by ~1e-4 nmi; "reassoc" did the same to an optimization). Where a reciprocal pays, the source computes it once.
FASTMATH = False
# njit(allocates=False): a kernel that creates no array (it reads and writes the arrays it is given and returns
# numbers) is compiled without numba's reference-counting runtime (NRT). With it, every array argument costs an
# atomic increment and decrement at each call: in the integrator's right-hand side (dynamics.evaluate and what it
# calls) 40 % of the time of a trajectory (bench/bench_sample.py). The arithmetic is the same.


def python_function(f: Any) -> Any:
    """The plain Python function behind a compiled one (for callers that pass symbolic values)."""
    return getattr(f, "py_func", f)


if NO_JIT:

    def _njit(*args: Any, allocates: bool = True, **kwargs: Any) -> Any:
        if len(args) == 1 and callable(args[0]) and not kwargs:
            return args[0]
        return lambda f: f

else:
    import numba

    def _cache_dir() -> str:
        digest = hashlib.sha256()
        for source in sorted(Path(__file__).parent.glob("*.py")):
            text = source.read_bytes()
            if not re.search(rb"^(import casadi|from footprint.core import collocation)", text, re.MULTILINE):
                digest.update(text)
        root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "footprint"
        return str(root / f"numba-{numba.__version__}-{digest.hexdigest()[:16]}")

    if not os.environ.get("NUMBA_CACHE_DIR"):
        numba.config.CACHE_DIR = _cache_dir()  # type: ignore[attr-defined]  # numba's config is set at run time

    def _njit(*args: Any, allocates: bool = True, **kwargs: Any) -> Any:
        options: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy", "fastmath": FASTMATH}
        if not allocates:
            options["_nrt"] = False
        options.update(kwargs)
        if len(args) == 1 and callable(args[0]):
            return numba.njit(**options)(args[0])
        return numba.njit(*args, **options)


_F = TypeVar("_F", bound=Callable[..., Any])


# njit(f) is typed as f itself, njit(signature or options) as a decorator that keeps the function's type: callers are
# checked against a kernel's annotations (a numba dispatcher is called as the function it compiles). One definition
# over the two _njit above, which mypy could not overload each.
@overload
def njit(f: _F, /) -> _F: ...
@overload
def njit(*args: Any, allocates: bool = True, **kwargs: Any) -> Callable[[_F], _F]: ...
def njit(*args: Any, allocates: bool = True, **kwargs: Any) -> Any:
    return _njit(*args, allocates=allocates, **kwargs)


# A compiled loop that runs long (the guidance's cycles) asks Python "stop now?" (a time limit, a cancel) through a
# token it is given, 0 when no one asks: asks_stop(token) calls what `asking` holds under it, in numba's object mode,
# which takes the GIL for the call (a few microseconds; a guided flight asks once a prediction).
_ASKED: dict[int, Callable[[], bool]] = {}
_TOKENS = itertools.count(1)


@contextmanager
def asking(stop: Callable[[], bool] | None) -> Iterator[int]:
    """The token asks_stop takes to ask `stop` while the block runs (0: none to ask)."""
    if stop is None:
        yield 0
        return
    token = next(_TOKENS)
    _ASKED[token] = stop
    try:
        yield token
    finally:
        del _ASKED[token]


def _stop_asked(token: int) -> bool:
    return bool(_ASKED[token]())


if NO_JIT:

    def asks_stop(token: int) -> bool:
        """Whether what `asking` holds under token (none: 0) asks to stop."""
        return token != 0 and _stop_asked(token)

else:

    @numba.njit(cache=True)  # not nogil: object mode holds the GIL for the call
    def asks_stop(token: int) -> bool:
        """Whether what `asking` holds under token (none: 0) asks to stop."""
        if token == 0:
            return False
        with numba.objmode(stop="boolean"):
            stop = _stop_asked(token)
        return stop

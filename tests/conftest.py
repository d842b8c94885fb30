"""Property-based tests draw the same examples on every run (CI must not fail on a new random draw);
set HYPOTHESIS_PROFILE=explore to search afresh."""

import os

import pytest
from hypothesis import settings

settings.register_profile("repeatable", derandomize=True, print_blob=True)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "repeatable"))

# Starlette's TestClient and schemathesis' ASGI calls name the host "testserver": the service serves it in tests only
os.environ.setdefault("FOOTPRINT_ALLOWED_HOSTS", "testserver")


def _same(a, b, rel, path):
    """Equal structure and text, floats to `rel`: NumPy's SIMD loops may round the last bit of an array's
    tail differently in another process (alignment), so numbers from a worker match a serial run only so."""
    import dataclasses
    import math

    if dataclasses.is_dataclass(a):
        assert type(a) is type(b), path
        a, b = dataclasses.asdict(a), dataclasses.asdict(b)
    if isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), path
        for k in a:
            _same(a[k], b[k], rel, f"{path}.{k}")
    elif isinstance(a, (list, tuple)):
        assert isinstance(b, (list, tuple)) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, rel, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, float):
        assert math.isclose(a, b, rel_tol=rel, abs_tol=rel), f"{path}: {a!r} != {b!r}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


@pytest.fixture
def same_numbers():
    """assert_same(a, b): equal but for the last bits of floats (rel 1e-12)."""
    return lambda a, b, rel=1e-12: _same(a, b, rel, "")

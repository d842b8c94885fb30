"""All numba settings in one place.

Set FOOTPRINT_NO_JIT=1 to run the same kernels as plain Python (slow; for debugging and coverage).
Compiled functions are cached on disk (numba's __pycache__ next to the module) so that a new process
starts in well under a second once the cache is warm.
"""

import os

NO_JIT = os.environ.get("FOOTPRINT_NO_JIT", "") not in ("", "0")
# LLVM fast-math flags that keep IEEE NaN and infinity semantics (events use NaN for "inactive"):
# contraction into fused multiply-add, reciprocal approximation, reassociation, no signed zeros.
FASTMATH = {"contract", "arcp", "reassoc", "nsz"}

if NO_JIT:

    def njit(*args, **kwargs):
        if len(args) == 1 and callable(args[0]) and not kwargs:
            return args[0]
        return lambda f: f

else:
    import numba

    def njit(*args, **kwargs):
        options = {"cache": True, "nogil": True, "error_model": "numpy", "fastmath": FASTMATH}
        options.update(kwargs)
        if len(args) == 1 and callable(args[0]):
            return numba.njit(**options)(args[0])
        return numba.njit(*args, **options)

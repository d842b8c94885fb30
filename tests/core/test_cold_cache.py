"""A dispersion flown on a cold numba cache in this process and on two Dask workers that start once this process
has filled the cache gives the same bits (core._jit: no fast-math). With LLVM's "contract" and "arcp" it did not, its
samples flown by DOP853: 44 of its 240 landings were up to 1e-4 nmi apart, because LLVM fuses and reciprocates what it
sees after inlining and a kernel compiled in one process inlined otherwise than its copy loaded from the cache in
another. Whether it shows depends on how LLVM inlines the code of the day: it failed on cac47fe's code (DOP853 then the
default) with the old flags put back; on later code they happened to agree here. On a warm cache
(tests/service/test_dispersion_jobs.py) both sides load the same code and agree."""

import os
import subprocess
import sys

from tests.service.test_dispersion_jobs import STUDY

FLY = f"""
import copy
import numpy as np
from footprint.api import disperse
if __name__ == "__main__":
    study = {STUDY!r}
    study["footprint"]["case"]["integrator"] = {{"method": "dop853"}}
    here, _ = disperse(copy.deepcopy(study))
    there, info = disperse(copy.deepcopy(study), workers=2)
    assert info["workers"] == 2, info
    print(sum(int(np.sum(np.asarray(here.clouds[k]) != np.asarray(there.clouds[k]))) for k in here.clouds))
"""


def test_a_dispersion_on_a_cold_cache_gives_the_same_bits_here_and_on_workers(tmp_path):
    """~25 s: the flight's kernels compiled on an empty cache, then two worker processes."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"))
    script = tmp_path / "fly.py"  # a file, so that the workers' processes can import the main module
    script.write_text(FLY)
    r = subprocess.run([sys.executable, str(script)], env=env, capture_output=True, text=True, check=True, cwd=tmp_path)
    assert r.stdout.split()[-1] == "0", r.stdout

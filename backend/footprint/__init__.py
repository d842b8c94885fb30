"""Footprint: landing footprints of lifting entry vehicles (AFWAL-TR-82-3036).

`from footprint import fly` is the Python door. Importing `footprint.core` alone pulls in only numpy and
numba (the top level loads the pydantic case contract lazily).
"""

__all__ = ["Trajectory", "fly"]
__version__ = "0.1.0"


def __getattr__(name):
    if name == "fly":
        from footprint.api import fly

        return fly
    if name == "Trajectory":
        from footprint.core.trajectory import Trajectory

        return Trajectory
    raise AttributeError(name)

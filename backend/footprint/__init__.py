"""Footprint: landing footprints of lifting entry vehicles (AFWAL-TR-82-3036).

`from footprint import fly, footprint, disperse` is the Python door. Importing `footprint.core` alone pulls in only
numpy and numba (the top level loads the pydantic case contract lazily).
"""

__all__ = ["Footprint", "Trajectory", "disperse", "fly", "footprint"]
__version__ = "0.1.0"


def __getattr__(name):
    if name in ("fly", "footprint", "disperse"):
        from footprint import api

        return getattr(api, name)
    if name == "Footprint":
        from footprint.core.footprints import Footprint

        return Footprint
    if name == "Trajectory":
        from footprint.core.trajectory import Trajectory

        return Trajectory
    raise AttributeError(name)

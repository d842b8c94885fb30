"""Errors the core raises for a user's input. The CLI and the service turn them into one line."""


class InputError(ValueError):
    """A field of a case, vehicle or study is out of its allowed range or inconsistent.

    `field` is the dotted path of the offending field (e.g. "vehicle.aero.tables.cl.mach");
    the message says the value and what is allowed.
    """

    def __init__(self, field: str, message: str):
        super().__init__(f"{field}: {message}")
        self.field = field
        self.message = message


class NoOptimum(RuntimeError):
    """A collocation ended without an optimum (IPOPT's status and the largest violation): the job's one line."""


class Stopped(RuntimeError):
    """A long computation stopped because its on_progress asked it to (a cancelled job)."""

"""A request's mistakes as the CLI and the service say them: one line naming each field and what is allowed, every
echo of the client's text printable and clipped; the fields as data (error_parts) for the service's 422 body."""

import dis
import functools
import re
import sysconfig
from collections.abc import Sequence
from pathlib import Path
from typing import Any, get_args

from pydantic import ValidationError

from footprint.contracts.doors import uncomputed
from footprint.core.errors import InputError


def error_line(exc: ValidationError | InputError) -> str:
    """One line naming the field(s) and the allowed range."""
    return "; ".join(text for _, text in error_parts(exc))


def error_parts(exc: ValidationError | InputError) -> list[tuple[str | None, str]]:
    """(field, its part of the line) for each field in error, the field as a dotted path (None for the request as a
    whole); the last part counts the fields past MAX_ERROR_FIELDS."""
    if isinstance(exc, InputError):
        return [(exc.field, clip(printable(str(exc)), ERROR_MESSAGE_CHARS))]
    return errors_parts(exc.errors())


def errors_parts(errs: Sequence[Any]) -> list[tuple[str | None, str]]:
    """error_parts of pydantic's errors (ValidationError.errors(), or the framework's for a body)."""
    parts: list[tuple[str | None, str]] = []
    tags = union_tags()
    for err in errs[:MAX_ERROR_FIELDS]:
        loc = []
        for i, x in enumerate(err["loc"]):
            after = err["loc"][i - 1] if i else None
            study = after in ("study", "footprint")  # a job's study, a dispersion's footprint study
            if isinstance(x, str) and (
                (after in (None, "bank", "alpha", "heating") or study) and x in tags or (study and x in _STUDY_TAGS)
            ):
                continue  # a discriminated union's tag (a law, a study's method), not a field
            if _member_label(x) and not (err["type"] == "extra_forbidden" and i == len(err["loc"]) - 1):
                continue  # a union member's tag or pydantic's label of it, not a field (an unknown key is the client's)
            loc.append(clip(printable(str(x)), ECHO_CHARS))  # a key is the client's text too
        msg = clip(printable(err["msg"].removeprefix("Value error, ")), ERROR_MESSAGE_CHARS)  # may quote the input
        if err["type"] == "value_error" and said_by_python(err.get("ctx", {}).get("error")):
            msg = clip(printable(uncomputed(err["ctx"]["error"])), ERROR_MESSAGE_CHARS)
        if err["type"] in ("union_tag_invalid", "union_tag_not_found"):  # a law's or a study's tag: name it
            ctx = err.get("ctx", {})
            tag, allowed = ctx.get("discriminator", "").strip("'"), ctx.get("expected_tags", "")
            loc.append(tag)
            if "tag" in ctx:
                msg = f"{ctx['tag']!r} is not one of {allowed}"
            else:
                msg = "missing" + (f"; one of {allowed}" if allowed else "")
            if (
                tag == "method"
                and err["type"] == "union_tag_not_found"
                and isinstance(err.get("input"), dict)
                and "vehicle" in err["input"]
            ):
                msg += " (this looks like a case: a study holds it as 'case' and names its 'method')"
        elif err["type"] not in ("missing", "value_error") and "input" in err:
            msg += f" (got {_short(err['input'])})"
        below = _FIELD_FIRST.match(msg)  # a model validator's message names the field below its location
        if loc and below:
            parts.append((f"{'.'.join(loc)}.{below.group(1)}", f"{'.'.join(loc)}.{msg}"))
        elif loc:
            parts.append((".".join(loc), f"{'.'.join(loc)}: {msg}"))
        else:
            parts.append((below.group(1) if below else None, msg))
    if len(errs) > MAX_ERROR_FIELDS:
        field, text = parts[-1]
        parts[-1] = (field, text + f" (and {len(errs) - MAX_ERROR_FIELDS:,} more fields with errors)")
    return parts


_FIELD_FIRST = re.compile(r"^([A-Za-z_][\w.]*): ")


PACKAGE_DIR = str(Path(__file__).resolve().parents[1])  # footprint/, wherever it is installed
LIBRARY_DIRS = tuple({sysconfig.get_paths()[k] for k in ("stdlib", "platstdlib", "purelib", "platlib")})
_RAISES = {dis.opmap["RAISE_VARARGS"], dis.opmap["RERAISE"]}


def said_by_python(exc: object) -> bool:
    """A ValueError in a validator that no `raise` of a validator's code wrote, but a call it made (math.sqrt's domain
    error, int()'s) or a library (numpy's): its words are Python's, not a reason the user can act on. An InputError
    is always the core's."""
    if not isinstance(exc, ValueError) or isinstance(exc, InputError) or exc.__traceback__ is None:
        return False
    tb = exc.__traceback__
    while tb.tb_next is not None:
        tb = tb.tb_next
    file = tb.tb_frame.f_code.co_filename
    ours = file.startswith(PACKAGE_DIR) or not file.startswith(LIBRARY_DIRS)
    return not (ours and tb.tb_frame.f_code.co_code[tb.tb_lasti] in _RAISES)


def _member_label(x: object) -> bool:
    """A union member in an error's location: its tag, "(number)" (contracts.fields.shape_tag), or pydantic's label
    of an untagged one, "list[function-after[check(), ...]]"; no field's name holds a parenthesis or a bracket."""
    return isinstance(x, str) and any(c in x for c in "([")


# what of a bad request an error line echoes: never the whole of a 200 kB value
ECHO_CHARS = 80  # an input value or a key
ERROR_MESSAGE_CHARS = 500  # one field's message
MAX_ERROR_FIELDS = 20  # fields named in one line; the rest counted


def printable(text: str) -> str:
    """Text that stays on its line: a line break, NUL, ESC or other character that does not print (a lone surrogate
    too) written as Python writes it in a string literal ("a\\nb"); a client's key or value may hold any of them."""
    return text if text.isprintable() else "".join(ch if ch.isprintable() else repr(ch)[1:-1] for ch in text)


def clip(text: str, limit: int) -> str:
    """Text cut at limit characters ("..." marks the cut)."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _short(value: object, limit: int = ECHO_CHARS) -> str:
    """A user's input as it lands in a one-line error: repr, cut at limit characters."""
    return clip(repr(value), limit)


@functools.cache
def union_tags() -> frozenset[str]:
    """The tags of the discriminated unions a request holds (bank, alpha and heating laws, footprint study methods):
    pydantic puts the chosen tag in an error's location, which names the law, not a field."""
    from footprint.contracts import case, footprint

    tags: set[str] = set()
    for union in (case.BankCase, case.AlphaCase, case.HeatingCase, footprint.FootprintStudy):
        for model in get_args(get_args(union)[0]):
            for name in ("law", "model", "method"):
                if name in model.model_fields:
                    tags.update(get_args(model.model_fields[name].annotation))
    return frozenset(tags - _STUDY_TAGS)  # a method that is also a field name is a tag only below a study


_STUDY_TAGS = {"collocation"}  # a study's method that is also a field name (the optimization's "collocation")

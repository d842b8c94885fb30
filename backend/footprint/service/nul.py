"""The NUL character, refused at the edge (GuardMiddleware) in every text a request carries: Postgres stores no NUL in
a text or JSON column, and a name or study that holds one used to fail as a 500 (or as a job failing with the SQL).
One check of the path, the query and the body covers every text the service stores, whichever model reads it."""

import json
import re
from urllib.parse import parse_qsl

from footprint.service.errors import NotFound, RequestInvalid

# in JSON a NUL is the escape \u0000 after an even run of backslashes (an odd run ends in an escaped backslash)
JSON_NUL = re.compile(rb"(?<!\\)(?:\\\\)*\\u0000")
WHY = "text may not hold the NUL character (\\u0000)"


def refusal(path: str, query: bytes, body: bytes | None, content_type: str) -> Exception | None:
    """A 404 for a path holding NUL (no stored id does), a 422 naming the query parameter or the body's field that
    holds one; None when none does (or the body is not JSON: the route then says so)."""
    if "\x00" in path:
        return NotFound(f"no such path: {path[:200]!r} ({WHY})")
    if b"%00" in query or b"\x00" in query:
        for key, value in parse_qsl(query.decode("latin-1"), keep_blank_values=True):
            if "\x00" in key + value:
                field = "query" if "\x00" in key else key[:80]
                return RequestInvalid(f"{field}: {WHY}", field)
    if not body:
        return None
    if b"\x00" in body:  # raw: a CSV (or any non-JSON) body; its line, as the CSV's other errors name it
        line = body[: body.index(b"\x00")].count(b"\n") + 1
        field = f"line {line}" if "csv" in content_type else "body"
        return RequestInvalid(f"{field}: {WHY}", field)
    if JSON_NUL.search(body):
        try:
            field = _field_with_nul(json.loads(body))
        except (ValueError, RecursionError):
            return None
        if field is not None:
            return RequestInvalid(f"{field}: {WHY}", field)
    return None


def _field_with_nul(data) -> str | None:
    """The dotted path of the first string holding NUL (a key holding one: the object that has it)."""
    stack = [("", data)]
    while stack:
        where, node = stack.pop()
        if isinstance(node, str) and "\x00" in node:
            return where or "body"
        if isinstance(node, dict):
            if any("\x00" in key for key in node):
                return where or "body"
            stack.extend((f"{where}.{k}" if where else k, v) for k, v in reversed(node.items()))
        elif isinstance(node, list):
            stack.extend((f"{where}.{i}" if where else str(i), v) for i, v in reversed(list(enumerate(node))))
    return None

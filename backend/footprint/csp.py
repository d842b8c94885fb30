"""Content-Security-Policy and text escaping shared by the service's responses and the standalone folium map
(issue 15 item 1: a footprint's name once ran as script inside a JS template literal).

The policies allow no inline script but the ones hashed here from our own templates, no plugin, no <base>, and
(sent as a header) no framing. Styles keep 'unsafe-inline': Leaflet's and folium's markup and the page's
innerHTML-built SVG carry style attributes, and a style cannot run script."""

import base64
import hashlib
import json
import re
from html import escape
from urllib.parse import urlsplit

# an inline <script> whose text runs: no src, and no data type such as application/json
_INLINE_SCRIPT = re.compile(r"<script(\s[^>]*)?>(.*?)</script>", re.S | re.I)
_DATA_TYPE = re.compile(r"""\btype\s*=\s*["']?application/(ld\+)?json""", re.I)
_SRC = re.compile(r"\bsrc\s*=", re.I)

SECURITY_HEADERS = {"X-Content-Type-Options": "nosniff", "Referrer-Policy": "no-referrer"}


def js_string(text: str) -> str:
    """text as a JavaScript string literal that is also safe inside an HTML <script> element: <, >, & and
    U+2028/2029 escaped (json.dumps' ensure_ascii escapes every other non-ASCII character)."""
    return (
        json.dumps(str(text))
        .replace("<", "\\u003c")
        .replace(">", "\\u003e")
        .replace("&", "\\u0026")
        .replace("\u2028", "\\u2028")
        .replace("\u2029", "\\u2029")
    )


def html_attribute(text: str) -> str:
    """text as a double-quoted HTML attribute value, quotes included."""
    return f'"{escape(str(text), quote=True)}"'


def inline_script_hashes(html: str) -> list[str]:
    """The CSP sources ('sha256-…') of every inline script of html, in order. Hash only HTML whose scripts come
    from our own templates with no user text in them: a hash allows whatever the script says."""
    found = []
    for attributes, text in _INLINE_SCRIPT.findall(html):
        if _SRC.search(attributes or "") or _DATA_TYPE.search(attributes or ""):
            continue
        digest = base64.b64encode(hashlib.sha256(text.encode("utf-8")).digest()).decode()
        if f"'sha256-{digest}'" not in found:
            found.append(f"'sha256-{digest}'")
    return found


def tile_source(tile_url: str) -> str | None:
    """The img-src source of a Leaflet tile URL template (FOOTPRINT_TILE_URL): its origin, a subdomain
    template field such as {s} as the wildcard CSP allows only as the leftmost label; None without a URL."""
    if not tile_url:
        return None
    parts = urlsplit(tile_url)
    host = parts.netloc.rsplit("@", 1)[-1]
    labels = host.split(".")
    templated = [("{" in label) for label in labels]
    if any(templated):
        if templated[0] and not any(templated[1:]):
            host = ".".join(["*"] + labels[1:])
        else:  # a template field past the first label cannot be written as a CSP host
            return f"{parts.scheme}:"
    return f"{parts.scheme}://{host}"


def policy(directives: dict[str, list[str]]) -> str:
    return "; ".join(f"{name} {' '.join(sources)}" for name, sources in directives.items())


def page_policy(tile_url: str = "", script_hashes: list[str] = ()) -> str:
    """The service's policy for the page, its static files, the API and the docs: scripts only from the service
    (and the inline ones of script_hashes: /docs' Swagger UI set-up)."""
    tiles = tile_source(tile_url)
    return policy(
        {
            "default-src": ["'self'"],
            "script-src": ["'self'", *script_hashes],
            "style-src": ["'self'", "'unsafe-inline'"],
            "img-src": ["'self'", "data:", "blob:"] + ([tiles] if tiles else []),
            "connect-src": ["'self'"],
            "font-src": ["'self'", "data:"],
            "worker-src": ["'self'", "blob:"],  # ReDoc's search runs in a blob: worker
            "object-src": ["'none'"],
            "base-uri": ["'none'"],
            "form-action": ["'self'"],
            "frame-ancestors": ["'none'"],
        }
    )


def standalone_policy(script_hashes: list[str], *, header: bool) -> str:
    """The policy of a self-contained HTML file (the folium map): nothing loaded, only the hashed inline scripts.
    frame-ancestors only in a header: chromium reports it as an error in a <meta> tag, where it is ignored."""
    directives = {
        "default-src": ["'none'"],
        "script-src": script_hashes or ["'none'"],
        "style-src": ["'unsafe-inline'"],
        "img-src": ["data:"],
        "object-src": ["'none'"],
        "base-uri": ["'none'"],
        "form-action": ["'none'"],
    }
    if header:
        directives["frame-ancestors"] = ["'none'"]
    return policy(directives)


def with_policy_meta(html: str, content_policy: str) -> str:
    """html with the policy as the first element of its <head> (a file opened from disk gets no headers)."""
    meta = f'<meta http-equiv="Content-Security-Policy" content={html_attribute(content_policy)}>'
    head = re.search(r"<head[^>]*>", html, re.I)
    if head is None:
        raise ValueError("the HTML has no <head> for its Content-Security-Policy")
    return f"{html[: head.end()]}\n{meta}{html[head.end() :]}"

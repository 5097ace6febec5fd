"""How a tab's address reaches the server: a link ``http://HOST:PORT/?scene=CODE``, the page's own URL, and
whether the browser asks for reduced motion (app.panel.motion).

viser passes no URL parameter to Python (its websocket handshake asks for ``/`` whatever the page's query), but
it lets the server read the browser's storage (``client.local_storage``, viser 1.1). So the page viser serves
gets a few lines of script, run before viser's client starts, that copy the page's address and its ``scene``
parameter into that storage, under viser's prefix for the keys it reads; the session reads them when the tab
connects (``app.share.panel``). Class mode's ``class`` parameter (the lecturer's key) goes there too, or is
removed when the address has none (app.serve.classroom reads it). The script is the same text for every
request: nothing from the request is written into the page, so a crafted address cannot inject markup.

Like ``app.serve.guard``, this wraps ``websockets.asyncio.server.serve`` once, before the server starts, and changes
only the HTML page viser returns (whatever wraps the same function, the guard's refusals pass through as they
are).
"""

from __future__ import annotations

import gzip
import threading

STORAGE_PREFIX = "viser-user:"  # viser 1.1's prefix for the keys client.local_storage reads (read in a browser)
PAGE_KEY = "quasirigid.page"  # the page's own address (origin and path), for the link the Share button shows
LINK_KEY = "quasirigid.link"  # the scene parameter of the address the tab was opened with
MOTION_KEY = "quasirigid.motion"  # "reduce" when the browser asks for reduced motion (app.panel.motion)
CLASS_KEY = "quasirigid.class"  # class mode: the class parameter of the address (the lecturer's key), or none
MAX_CLASS_CHARS = 200  # what the script copies of a class parameter (a key is 22 characters)
MAX_LINK_CHARS = 100_000  # what the script copies of a scene parameter (app.share.code.MAX_CODE_CHARS)

SCRIPT = f"""<script>/* Quasirigid (app/share/link.py): the page's address and its scene parameter, for the server */
(function () {{
  try {{
    var s = window.localStorage, q = new URLSearchParams(window.location.search), code = q.get("scene"),
        klass = q.get("class");
    s.setItem("{STORAGE_PREFIX}{PAGE_KEY}", window.location.origin + window.location.pathname);
    var still = window.matchMedia && window.matchMedia("(prefers-reduced-motion: reduce)").matches;
    s.setItem("{STORAGE_PREFIX}{MOTION_KEY}", still ? "reduce" : "no-preference");
    if (code !== null) s.setItem("{STORAGE_PREFIX}{LINK_KEY}", code.slice(0, {MAX_LINK_CHARS}));
    if (klass !== null) s.setItem("{STORAGE_PREFIX}{CLASS_KEY}", klass.slice(0, {MAX_CLASS_CHARS}));
    else s.removeItem("{STORAGE_PREFIX}{CLASS_KEY}");
  }} catch (e) {{}}
}})();
</script>""".encode()

# the request line a link arrives on may be this long (bytes): a longest code, percent-encoded, with room to spare;
# websockets' own limit for a line is 8 kB, past which it closed the connection unanswered (the browser's
# ERR_EMPTY_RESPONSE for a 9 kB link). A longer line is dropped as it arrives and answered with TOO_LONG_PAGE.
MAX_REQUEST_LINE = 4 * MAX_LINK_CHARS
TOO_LONG = "/?quasirigid-link-too-long"  # the stand-in request line of a line dropped as too long
TOO_LONG_PAGE = (
    "<!doctype html><meta charset='utf-8'><title>Quasirigid: link too long</title>"
    "<p><b>This link is too long for the explorer.</b> Its scene code would be more than {limit} characters; a "
    "scene's code is a few thousand at most, so the link was probably cut, joined or altered.</p>"
    "<p>Open <a href='/'>the explorer</a> and paste the code into Share, or load the scenario's TOML file.</p>")

_lock = threading.Lock()
_installed = False
_pages: dict[tuple[int, bool], bytes] = {}  # (id of viser's cached page, gzipped) -> the page with the script
_scripts: list[bytes] = []  # the app's other page scripts (app.panel.typed_numbers), after SCRIPT


def with_script(html: bytes) -> bytes:
    """viser's page with SCRIPT (and the scripts ``install`` was given) at the start of its head, so they run
    before the client's own script."""
    head = html.find(b"<head>")
    at = head + len(b"<head>") if head >= 0 else 0
    return html[:at] + SCRIPT + b"".join(_scripts) + html[at:]


def _page_response(response):
    """viser's response with the script in its HTML page; any other response as it is."""
    from websockets.datastructures import Headers
    from websockets.http11 import Response

    if response is None or getattr(response, "status_code", None) != 200:
        return response
    headers = response.headers
    if not str(headers.get("Content-Type", "")).startswith("text/html"):
        return response
    gzipped = headers.get("Content-Encoding", "") == "gzip"
    key = (id(response.body), gzipped)  # viser keeps one bytes object per file: its id names the page
    with _lock:
        body = _pages.get(key)
        if body is None:
            html = gzip.decompress(response.body) if gzipped else bytes(response.body)
            body = with_script(html)
            body = gzip.compress(body) if gzipped else body
            if len(_pages) > 8:  # a handful of pages at most; bounded all the same
                _pages.clear()
            _pages[key] = body
    out = Headers()
    for name, value in headers.raw_items():
        if name.lower() != "content-length":
            out[name] = value
    out["Content-Length"] = str(len(body))
    return Response(200, response.reason_phrase, out, body)


def link_too_long(path: str) -> bool:
    """Whether a request for ``path`` carries a link the explorer cannot take: a scene parameter longer than
    MAX_LINK_CHARS, or a request line dropped as too long (TOO_LONG)."""
    from urllib.parse import parse_qs, urlsplit

    if path == TOO_LONG:
        return True
    query = urlsplit(path).query
    return len(query) > MAX_LINK_CHARS and any(len(v) > MAX_LINK_CHARS for v in parse_qs(query).get("scene", []))


def too_long_response():
    from websockets.datastructures import Headers
    from websockets.http11 import Response

    body = TOO_LONG_PAGE.format(limit=MAX_LINK_CHARS).encode()
    return Response(414, "URI Too Long", Headers({"Content-Type": "text/html; charset=utf-8",
                                                  "Content-Length": str(len(body))}), body)


def _long_request_lines() -> None:
    """Let an HTTP request's first line be up to MAX_REQUEST_LINE bytes (a header line keeps websockets' limit),
    and drop a longer one as it arrives, standing in TOO_LONG for it, so the browser gets a page that says so
    rather than an empty response. Reaches into websockets' Request.parse and its stream reader (websockets
    13-16); other versions are left as they are."""
    from websockets import http11

    original = http11.Request.parse.__func__
    if getattr(original, "quasirigid", False):
        return

    def parse(cls, read_line):
        first = [True]
        reader = getattr(read_line, "__self__", None)

        def read_first_long(limit):
            if not first[0]:
                return (yield from read_line(limit))
            first[0] = False
            try:
                return (yield from read_line(max(limit, MAX_REQUEST_LINE)))
            except RuntimeError:
                buffer = getattr(reader, "buffer", None)
                if not isinstance(buffer, bytearray):
                    raise
            while (end := buffer.find(b"\n")) < 0:  # drop the line as it arrives, to its end
                if reader.eof:
                    raise EOFError("stream ended inside an overlong request line")
                del buffer[:]
                yield
            del buffer[:end + 1]
            return f"GET {TOO_LONG} HTTP/1.1\r\n".encode()

        return (yield from original(cls, read_first_long))

    parse.quasirigid = True
    http11.Request.parse = classmethod(parse)


def install(*scripts: bytes) -> None:
    """Wrap websockets' server factory, so the servers made afterwards serve the page with the script (and
    ``scripts``, each a ``<script>`` element of the app's, added once) and answer a link too long with a page that
    says so."""
    global _installed
    with _lock:
        for script in scripts:
            if script not in _scripts:
                _scripts.append(script)
                _pages.clear()  # pages made before carry no such script
        if _installed:
            return
        import websockets.asyncio.server as ws_server

        original = ws_server.serve
        _long_request_lines()

        def serve(handler, *args, process_request=None, **kwargs):
            def with_page(connection, request):
                if link_too_long(request.path):
                    return too_long_response()
                response = process_request(connection, request) if process_request is not None else None
                return _page_response(response)

            return original(handler, *args, process_request=with_page, **kwargs)

        ws_server.serve = serve
        _installed = True


__all__ = ["CLASS_KEY", "LINK_KEY", "MAX_REQUEST_LINE", "MOTION_KEY", "PAGE_KEY", "SCRIPT", "STORAGE_PREFIX", "install",
           "link_too_long", "with_script"]

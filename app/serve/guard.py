"""Who may talk to the explorer. A web page the user visits in another tab can open a websocket to any
local port, and a page on a hostile domain can rebind its name to 127.0.0.1 (DNS rebinding); viser accepts
both. So every HTTP request and websocket handshake is checked before viser sees it:

- the Host header must name the address the server is bound to (for a loopback bind: 127.0.0.1,
  localhost or [::1], with the bound port), unless the server was bound to every interface on purpose;
- a browser's Origin header, when present, must be the same origin as the page (http://HOST:PORT with the
  Host above), or one the user allowed with ``--allow-origin``. Clients that are not browsers send no
  Origin (the bench's websocket clients); they cannot be driven by another site, so they pass.

viser builds its websockets server inside a closure, so the check is installed by wrapping
``websockets.asyncio.server.serve`` once, in this process, before the server starts.
"""

from __future__ import annotations

import http
import logging
import threading

from .message_guard import install_frame_check
from .upload_cap import MAX_MESSAGE_BYTES

LOOPBACK_NAMES = ("127.0.0.1", "localhost", "[::1]", "::1")
EVERY_INTERFACE = ("0.0.0.0", "::", "[::]")

_lock = threading.Lock()
_policy: dict = {"host": "127.0.0.1", "origins": ()}
_installed = False


def configure(host: str, allow_origins: tuple[str, ...] = ()) -> None:
    """The bound host and the extra origins to accept, for servers started from now on."""
    with _lock:
        _policy["host"] = host
        _policy["origins"] = tuple(o.rstrip("/").lower() for o in allow_origins)
    install()


def refusal(headers, port: int, host: str | None = None, origins: tuple[str, ...] | None = None) -> str | None:
    """Why a request with these headers, arriving on ``port``, is refused; None when it is accepted."""
    host = _policy["host"] if host is None else host
    origins = _policy["origins"] if origins is None else origins
    if (twice := duplicated(headers)) is not None:
        return f"{twice} header given more than once"
    given = (headers.get("Host") or "").strip().lower()
    if host not in EVERY_INTERFACE:
        names = LOOPBACK_NAMES if host in LOOPBACK_NAMES else (host.lower(), f"[{host.lower()}]")
        allowed = {f"{n}:{port}" for n in names}
        if given not in allowed:
            return f"Host header {given[:80]!r} is not this server's address ({sorted(allowed)[0]})"
    origin = headers.get("Origin")
    if origin is None:
        return None  # not a browser: no other site can drive it
    origin = origin.strip().rstrip("/").lower()
    if origin == f"http://{given}" or origin in origins:
        return None
    return (f"Origin {origin[:80]!r} is not this page's origin (http://{given[:80]}); start the explorer with "
            "--allow-origin ORIGIN to accept another")


def duplicated(headers) -> str | None:
    """The name of the Host or Origin header a request gives more than once (which one would count is
    ambiguous: it is refused as malformed, 400), or None."""
    get_all = getattr(headers, "get_all", None)
    for name in ("Host", "Origin"):
        if get_all is not None and len(get_all(name)) > 1:
            return name
    return None


def refuse_share_tunnel(server) -> None:
    """viser answers any client's ShareUrlRequest by opening a public tunnel to the server through its share
    backend: one message from a page or a raw client would put an explorer bound to loopback on the internet,
    past the checks above. The explorer offers no share button (the panel hides viser's), so the requests are
    dropped: viser ignores a message no handler is registered for. A viser without the handler table is left
    as it is."""
    from viser import _messages as msgs

    handlers = getattr(getattr(server, "_websock_server", None), "_incoming_handlers", None)
    if handlers is not None:
        for cls in (msgs.ShareUrlRequest, msgs.ShareUrlDisconnect):
            handlers.pop(cls, None)


class _ClosedBeforeRequest(logging.Filter):
    """websockets logs every failed opening handshake as an error with its traceback, a client that closed the
    connection before its request was whole among them: a browser's speculative preconnect that it never used
    (chromium opens them to a page's origin), a port probe. Nobody's request failed there, so that record is
    dropped. viser drops every such record too, but only from the first request it serves on: a preconnect
    closed before that printed a traceback at start (a browser test's server log once failed on it). Installed
    before the server starts; a request that arrived and was malformed is left to viser's rule."""

    def filter(self, record: logging.LogRecord) -> bool:
        if record.getMessage() != "opening handshake failed" or not record.exc_info:
            return True
        exc = record.exc_info[1]
        while exc is not None:
            if isinstance(exc, EOFError):
                return False
            exc = exc.__cause__ or exc.__context__
        return True


def install() -> None:
    """Wrap websockets' server factory so that every server made afterwards checks requests first."""
    global _installed
    with _lock:
        if _installed:
            return
        logging.getLogger("websockets.server").addFilter(_ClosedBeforeRequest())
        import websockets.asyncio.server as ws_server
        from websockets.datastructures import Headers
        from websockets.http11 import Response

        original = ws_server.serve

        def serve(handler, *args, process_request=None, **kwargs):
            def checked(connection, request):
                port = connection.local_address[1] if connection.local_address else 0
                why = refusal(request.headers, port)
                if why is not None:
                    body = f"refused: {why}\n".encode()
                    # a header given twice is a malformed request (400); a wrong one is a refusal (403)
                    status = http.HTTPStatus.BAD_REQUEST if duplicated(request.headers) else http.HTTPStatus.FORBIDDEN
                    return Response(status, status.phrase,
                                    Headers({"Content-Type": "text/plain; charset=utf-8",
                                             "Content-Length": str(len(body))}), body)
                return process_request(connection, request) if process_request is not None else None

            # a client's message is read whole before anyone sees it: bounded far below viser's 50 MB
            kwargs["max_size"] = min(kwargs.get("max_size") or MAX_MESSAGE_BYTES, MAX_MESSAGE_BYTES)
            return original(handler, *args, process_request=checked, **kwargs)

        ws_server.serve = serve
        install_frame_check()  # and a frame that is no message is dropped, not a traceback ending the connection
        _installed = True

"""Where the explorer listens: ``--host`` and ``--port`` checked before the web server starts.

viser binds in a thread of its own and the start waits for it. Where it cannot bind it never says so: a host that
resolves to nothing or is no address of this machine left ``python -m app`` waiting for ever without a word, and
a port past 65535 printed viser's traceback and then waited for ever. A busy port viser skips, silently, to the
next free one. Here the same binding is tried first (every address the host resolves to, as asyncio's server
binds them), so a bad address is one line naming it and a busy port is said.
"""

from __future__ import annotations

import errno
import socket

LAST_PORT = 65535
SEARCH = 1000  # ports tried from the one asked, as viser tries them


class AddressError(ValueError):
    """``--host`` or ``--port`` cannot be listened on: the message names which, its value and what to give."""


def listening_port(host: str, port: int, dashes: str = "--") -> int:
    """The port to serve on: ``port`` when (host, port) can be bound now, else the next free one after it (0: any
    free port, left to the server). Raises AddressError for a port outside 0-65535, a host that resolves to
    nothing or is not this machine's, a port this user may not open, or no free port in the search; its message
    names ``{dashes}host`` or ``{dashes}port`` (the command line's options, or with "" the function's arguments)."""
    h, p = f"{dashes}host", f"{dashes}port"
    if isinstance(port, bool) or not isinstance(port, int) or not 0 <= port <= LAST_PORT:
        raise AddressError(f"{p} {port}: must be a whole number from 0 to {LAST_PORT} (0: any free port)")
    try:
        addresses = socket.getaddrinfo(host, None, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)
    except (OSError, UnicodeError, ValueError) as exc:  # gaierror is an OSError; an over-long label a UnicodeError
        raise AddressError(f"{h} {host}: resolves to no address ({_reason(exc)}); give an address or name of "
                           "this machine (default 127.0.0.1)") from None
    for candidate in [port] if port == 0 else range(port, min(port + SEARCH, LAST_PORT + 1)):
        failure = _bind_all(addresses, candidate)
        if failure is None:
            return candidate
        if failure.errno == errno.EADDRINUSE:
            continue
        if failure.errno in (errno.EACCES, errno.EPERM):
            raise AddressError(f"{p} {candidate}: this user may not listen on it ({_reason(failure)}; ports "
                               "below 1024 need administrator rights); give 0 for any free port, or one from 1024")
        raise AddressError(f"{h} {host}: cannot be listened on here ({_reason(failure)}); give an address of "
                           "this machine (default 127.0.0.1, this machine only)")
    raise AddressError(f"{p} {port}: it and the ports after it up to {min(port + SEARCH, LAST_PORT + 1) - 1} "
                       "are in use; give 0 for any free port")


def shown_host(host: str) -> str:
    """The host as a browser reaches it: every interface through loopback (IPv4's or IPv6's, as bound), an IPv6
    address in brackets (http://::1:8080 is no URL)."""
    host = {"0.0.0.0": "127.0.0.1", "::": "::1"}.get(host, host)
    return f"[{host}]" if ":" in host else host


def _bind_all(addresses, port: int) -> OSError | None:
    """Bind a listening socket on every address at ``port``, as asyncio's create_server does (address reuse on,
    IPv6 sockets IPv6 only), and close them; the first failure, or None."""
    opened = []
    try:
        for family, kind, proto, _name, address in addresses:
            s = socket.socket(family, kind, proto)
            opened.append(s)
            s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            if family == socket.AF_INET6 and hasattr(socket, "IPPROTO_IPV6"):
                s.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 1)
            s.bind((address[0], port, *address[2:]))
            s.listen(1)
        return None
    except OSError as exc:
        return exc
    finally:
        for s in opened:
            s.close()


def _reason(exc: BaseException) -> str:
    return getattr(exc, "strerror", None) or str(exc) or type(exc).__name__

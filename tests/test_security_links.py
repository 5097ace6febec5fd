"""Links, headers and the size of a client's messages (issue 24, point 4): a ``?scene=`` link the server cannot
take gets a page that says so (websockets answered a request line over 8 kB with nothing: the browser's
ERR_EMPTY_RESPONSE), and a link it can take still gets the explorer's page."""

from __future__ import annotations

import socket
import time

import pytest
from explorer_process import Explorer

from app.share.link import MAX_LINK_CHARS, MAX_REQUEST_LINE


@pytest.fixture(scope="module")
def app():
    from app.serve.server import App

    a = App(port=0)
    yield a
    a.close()


def _get(port: int, target: str, headers: tuple[str, ...] = ()) -> tuple[int, bytes]:
    """A raw HTTP/1.1 GET (the request line sent as it is, however long); (status, body)."""
    lines = [f"GET {target} HTTP/1.1", f"Host: 127.0.0.1:{port}", *headers, "Connection: close", "", ""]
    with socket.create_connection(("127.0.0.1", port), timeout=60) as s:
        s.sendall("\r\n".join(lines).encode())
        data = b""
        while chunk := s.recv(1 << 16):
            data += chunk
    assert data, "the server closed the connection without an answer"
    head, _, body = data.partition(b"\r\n\r\n")
    return int(head.split(b" ", 2)[1]), body


@pytest.mark.parametrize("chars", [9_000, MAX_LINK_CHARS + 1, MAX_REQUEST_LINE + 10, 3 * MAX_REQUEST_LINE])
def test_a_link_too_long_gets_a_page_that_says_so(app, chars):
    status, body = _get(app.port, "/?scene=qr1:" + "A" * chars)
    if chars <= MAX_LINK_CHARS:
        assert status == 200 and b"<script>" in body  # a long link the code can still judge: the explorer
    else:
        assert status == 414
        assert b"This link is too long" in body and str(MAX_LINK_CHARS).encode() in body


def test_a_short_link_gets_the_explorer(app):
    status, body = _get(app.port, "/?scene=qr1:abc")
    assert status == 200 and b"quasirigid.link" in body


@pytest.mark.parametrize("extra", [("Host: 127.0.0.1:{port}",), ("Host: attacker.example",),
                                   ("Origin: http://127.0.0.1:{port}", "Origin: http://127.0.0.1:{port}"),
                                   ("Origin: http://127.0.0.1:{port}", "Origin: http://attacker.example")])
def test_a_host_or_origin_given_twice_is_a_bad_request_not_a_server_error(app, extra):
    """websockets' Headers.get raised on a header given twice: a 500 (refused, but as a server fault)."""
    status, body = _get(app.port, "/", tuple(h.format(port=app.port) for h in extra))
    assert status == 400
    assert b"more than once" in body


@pytest.mark.parametrize("sent, kept", [(b"", False), (b"GET / HT", False),
                                         (b"NOT HTTP AT ALL\r\n\r\n", True)])
def test_a_connection_closed_before_its_request_leaves_no_traceback(sent, kept):
    """chromium opens speculative connections to a page's origin and may close them unused; websockets logged each
    as a failed opening handshake with its traceback, and viser's own filter drops those records only from the
    first request it serves on (a browser test's server log once failed on a preconnect closed before that). The
    explorer's filter, judged alone here, drops the record of a client that closed before its request was whole
    (websockets' own exception, from its protocol fed what the client sent) and keeps a malformed request's."""
    import logging

    from websockets.server import ServerProtocol

    from app.serve import guard

    guard.install()
    protocol = ServerProtocol()
    if sent:
        protocol.receive_data(sent)
    protocol.receive_eof()
    exc = protocol.handshake_exc
    assert exc is not None

    records: list[logging.LogRecord] = []

    class Keep(logging.Handler):
        def emit(self, record):
            records.append(record)

    logger = logging.getLogger("websockets.server")
    keep, filters = Keep(), logger.filters[:]
    logger.filters = [f for f in filters if type(f).__module__ == guard.__name__]  # not viser's, if it added one
    assert logger.filters
    logger.addHandler(keep)
    try:  # as websockets' server logs it (websockets/asyncio/server.py, conn_handler)
        logging.LoggerAdapter(logger, {}).error("opening handshake failed",
                                                exc_info=(type(exc), exc, exc.__traceback__))
    finally:
        logger.removeHandler(keep)
        logger.filters = filters
    assert len(records) == (1 if kept else 0)


def test_connections_closed_unused_at_start_print_no_traceback():
    """End to end: the explorer's server, before it has served any request (when viser's own filter is not yet
    there), gets three connections closed without a byte, as a browser's unused preconnects are."""
    with Explorer() as explorer:
        for _ in range(3):
            socket.create_connection(("127.0.0.1", explorer.port), timeout=10).close()
        time.sleep(2.0)  # no request in between: one would install viser's filter before their records
    log = explorer.log
    assert not any("Traceback" in line or "handshake failed" in line for line in log), "".join(log)

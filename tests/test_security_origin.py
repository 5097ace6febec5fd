"""Another site cannot drive the local explorer (issue 17): a websocket from a foreign Origin and a request
naming a foreign Host (DNS rebinding) are refused before viser sees them; the page's own origin, and
clients that are not browsers (no Origin), are served."""

from __future__ import annotations

import asyncio
import http.client

import pytest
import websockets
from websockets.exceptions import InvalidStatus

from app import __main__ as app_main
from app.serve.guard import refusal


@pytest.fixture(scope="module")
def port():
    from app.serve.server import App

    app = App(port=0)
    yield app.port
    app.close()


def _get(port: int, host: str) -> tuple[int, str]:
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    conn.request("GET", "/", headers={"Host": host})
    resp = conn.getresponse()
    body = resp.read().decode(errors="replace")
    conn.close()
    return resp.status, body


def _handshake(port: int, origin: str | None) -> int:
    """The HTTP status of a websocket handshake to the explorer (101 = accepted)."""

    async def go():
        headers = {"Origin": origin} if origin else None
        try:
            async with websockets.connect(f"ws://127.0.0.1:{port}", additional_headers=headers, open_timeout=10,
                                          subprotocols=["viser-v1.1.1"], origin=None):
                return 101
        except InvalidStatus as exc:
            return exc.response.status_code

    return asyncio.run(go())


def test_the_page_is_served_to_its_own_host_and_refused_to_a_rebound_name(port):
    status, body = _get(port, f"127.0.0.1:{port}")
    assert status == 200 and "<html" in body.lower()
    assert _get(port, f"localhost:{port}")[0] == 200
    status, body = _get(port, f"evil.example.com:{port}")
    assert status == 403 and "Host header" in body
    assert _get(port, f"127.0.0.1:{port + 1}")[0] == 403  # another port is another origin


def test_a_websocket_from_another_site_is_refused(port):
    assert _handshake(port, "http://evil.example.com") == 403
    assert _handshake(port, f"http://localhost.evil.example.com:{port}") == 403


def test_a_websocket_from_the_page_itself_or_from_no_browser_is_accepted(port):
    assert _handshake(port, f"http://127.0.0.1:{port}") == 101
    assert _handshake(port, None) == 101


@pytest.mark.parametrize(("host", "headers", "refused"), [
    ("127.0.0.1", {"Host": "127.0.0.1:80"}, False),
    ("127.0.0.1", {"Host": "[::1]:80", "Origin": "http://[::1]:80"}, False),
    ("127.0.0.1", {"Host": "attacker.example:80"}, True),
    ("127.0.0.1", {"Host": "127.0.0.1:80", "Origin": "http://attacker.example"}, True),
    ("127.0.0.1", {"Host": "127.0.0.1:80", "Origin": "null"}, True),  # a sandboxed or file:// page
    ("127.0.0.1", {}, True),  # HTTP/1.1 requires Host
    ("0.0.0.0", {"Host": "lab-pc.example:80", "Origin": "http://lab-pc.example:80"}, False),  # exposed on purpose
    ("0.0.0.0", {"Host": "lab-pc.example:80", "Origin": "http://attacker.example"}, True),
    ("192.0.2.7", {"Host": "192.0.2.7:80"}, False),
    ("192.0.2.7", {"Host": "127.0.0.1:80"}, True),
])
def test_the_rule(host, headers, refused):
    assert (refusal(headers, 80, host=host, origins=()) is not None) == refused


def test_an_allowed_origin_is_accepted_and_the_refusal_says_how():
    headers = {"Host": "127.0.0.1:80", "Origin": "https://course.example.org"}
    why = refusal(headers, 80, host="127.0.0.1", origins=())
    assert "--allow-origin" in why and "course.example.org" in why
    assert refusal(headers, 80, host="127.0.0.1", origins=("https://course.example.org",)) is None


def test_an_empty_host_is_an_error(capsys):
    assert app_main.main(["--host", "", "--port", "0"]) == 2
    assert "--host ''" in capsys.readouterr().err

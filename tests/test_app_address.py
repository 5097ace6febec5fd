"""Where the explorer listens (app.serve.address): a --host or --port that cannot be listened on is one line that
names it, before the web server starts. Until then viser waited for ever on such an address, without a word (a
host that is not this machine's) or after its own traceback (a port past 65535)."""

from __future__ import annotations

import socket
import subprocess
import sys

import pytest
from explorer_process import ROOT

from app.serve.address import LAST_PORT, AddressError, listening_port, shown_host

NOT_THIS_MACHINE = "192.0.2.1"  # TEST-NET-1 (RFC 5737): documentation only, never a machine's address
UNRESOLVABLE = "a" * 64 + ".example"  # a label over 63 characters: refused before any name lookup


@pytest.mark.parametrize("port", [-1, LAST_PORT + 1, 70_000, 2**63, 1.5, True, "8080"])
def test_a_port_outside_0_to_65535_is_named(port):
    with pytest.raises(AddressError, match=r"^--port .*: must be a whole number from 0 to 65535"):
        listening_port("127.0.0.1", port)


def test_a_host_that_resolves_to_nothing_is_named():
    with pytest.raises(AddressError, match=rf"^--host {UNRESOLVABLE}: resolves to no address"):
        listening_port(UNRESOLVABLE, 0)


def test_an_address_of_another_machine_is_named():
    with pytest.raises(AddressError, match=rf"^--host {NOT_THIS_MACHINE}: cannot be listened on here"):
        listening_port(NOT_THIS_MACHINE, 0)


def test_the_functions_arguments_are_named_without_dashes():
    with pytest.raises(AddressError, match=r"^port -1: "):
        listening_port("127.0.0.1", -1, dashes="")


def test_a_busy_port_moves_to_a_free_one_after_it():
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        busy = taken.getsockname()[1]
        if busy == LAST_PORT:
            pytest.skip("the system gave the last port: nothing after it to move to")
        port = listening_port("127.0.0.1", busy)
        assert port > busy
        with socket.socket() as s:
            s.bind(("127.0.0.1", port))  # free indeed


def test_the_last_port_busy_has_nowhere_to_go():
    with socket.socket() as taken:
        try:
            taken.bind(("127.0.0.1", LAST_PORT))
        except OSError:
            pytest.skip("port 65535 is taken on this machine")
        taken.listen(1)
        with pytest.raises(AddressError, match=r"^--port 65535: it and the ports after it up to 65535 are in use"):
            listening_port("127.0.0.1", LAST_PORT)


def test_a_free_port_is_kept_and_zero_is_left_to_the_server():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        free = s.getsockname()[1]
    assert listening_port("127.0.0.1", free) == free
    assert listening_port("127.0.0.1", 0) == 0


@pytest.mark.parametrize("host, shown", [("0.0.0.0", "127.0.0.1"), ("::", "[::1]"), ("::1", "[::1]"),
                                         ("127.0.0.1", "127.0.0.1"), ("localhost", "localhost")])
def test_the_printed_link_is_a_url(host, shown):
    assert shown_host(host) == shown


@pytest.mark.parametrize("argv, needle", [
    (["--host", NOT_THIS_MACHINE, "--port", "0"], f"error: --host {NOT_THIS_MACHINE}: cannot be listened on here"),
    (["--port", "70000"], "error: --port 70000: must be a whole number from 0 to 65535"),
    (["--port=-1"], "error: --port -1: must be a whole number from 0 to 65535"),
    (["--port", "-1e308"], "error: --port -1e308: must be a whole number from 0 to 65535"),
    (["--port", "1e3"], "error: --port 1e3: must be a whole number from 0 to 65535"),
    (["--port", "x" * 10_000], "error: --port " + "x" * 37 + "...: must be a whole number from 0 to 65535"),
])
def test_python_m_app_says_so_and_ends(argv, needle):
    """As a user starts it: one line and status 2, where it waited for ever (the timeout would fail this)."""
    res = subprocess.run([sys.executable, "-m", "app", *argv], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert res.returncode == 2, (res.stdout, res.stderr)
    assert needle in res.stderr and "Traceback" not in res.stdout + res.stderr
    assert [line for line in res.stderr.splitlines() if line.startswith("error: ")] == res.stderr.splitlines()[-1:]


def test_the_notebooks_show_refuses_them_before_serving():
    import app

    with pytest.raises(AddressError, match=rf"^host {NOT_THIS_MACHINE}: cannot be listened on here"):
        app.show(host=NOT_THIS_MACHINE, display=False)
    with pytest.raises(AddressError, match=r"^port 70000: must be"):
        app.show(port=70_000, display=False)

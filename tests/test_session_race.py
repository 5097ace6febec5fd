"""A tab that closes while its session is being built leaves no session behind (app.serve.server), on a live
server with raw websocket tabs."""

from __future__ import annotations

from test_class_mode import wait_until

from app.serve import server
from bench.class_client import Tab, run_tabs

TABS = 3


def test_tabs_that_close_while_their_session_is_built_leave_none():
    """viser runs the disconnect callback while the connect callback still builds the tab's Session: it found
    nothing to close, and the session then ran for no one (3 of 3 tabs gone 50 ms after connecting; 2 of 60
    bench-load clients)."""
    server.warm_up()
    app = server.App(host="127.0.0.1", port=0)
    url = f"ws://127.0.0.1:{app.port}"
    try:
        tabs = [Tab() for _ in range(TABS)]
        run_tabs(url, tabs, 0.05).join(timeout=60)  # gone 50 ms after connecting: long before a panel is built
        # each tab's session is built and then closed, or (its connect callback started after it had gone) never
        # built at all
        wait_until(lambda: app.stats.get("opened", 0) + app.stats.get("gone_before_built", 0) == TABS,
                   what="every tab's connect callback done")
        wait_until(lambda: app.stats.get("closed", 0) == app.stats.get("opened", 0), what="every session closed")
        assert app.sessions == {} and app._connecting == set()
        again = [Tab()]
        thread = run_tabs(url, again, 60.0)
        wait_until(lambda: len(app.sessions) == 1, what="a session for a new tab")
        wait_until(lambda: sum(again[0].counts) > 0, what="its run's frames")
    finally:
        app.close()
    thread.join(timeout=30)

"""How many tabs one server serves at once, and what a tab beyond them is told.

Every tab costs the server a thread and its state (~3 MB for a tab of its own run), so without a bound a flood of
connections (a script, a page reloaded in a loop) took memory and threads without end, and the tabs already open
stopped moving: `python -m bench load --clients 100 --minutes 0.5 --warmup 5` on two cores
(bench/results/load_100x05_unbounded.json) grew the server to 490 MB with 56 sessions built in 30 s, and their
clients' median share of their own frames was about 5 %. A tab beyond the bound gets one line saying so; its
connection holds no session.
"""

from __future__ import annotations

import os

import viser

# A bound on memory and threads, not a promise of smooth frames: ten tabs of their own run on two cores get most of
# theirs (tests/test_load.py), 60 get a few percent. 64 tabs take ~200 MB beyond the server's own; a class's
# following tabs cost less than their own runs do. Larger machines serve more.
TABS_PER_CORE = 32
MAX_TABS = max(64, TABS_PER_CORE * (os.cpu_count() or 1))


def full_note(client: viser.ClientHandle, what: str) -> None:
    """Tell a tab the server will not serve it now; ``what`` names what is full (the explorer, the class)."""
    try:
        client.gui.add_markdown(f"**Quasirigid** · {what} is full: this server serves {MAX_TABS} tabs at once "
                                f"and all are open. Reload this page once one of them has closed.")
    except Exception:  # noqa: BLE001 - the tab may already have gone; nothing to tell then
        pass

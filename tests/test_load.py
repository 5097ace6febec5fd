"""Load (issue 7): ten websocket clients on one explorer server (bench/load.py, a short version of
``python -m bench load --clients 10 --minutes 5``). The test asserts counts and ratios measured in one
run, which hold on a busy machine as on an idle one: each client received most of the frames the server
published for its session, no client was starved beside the others, no client saw an error, and every
session was opened, closed and freed. The updates-per-second target (30 for each client) and the memory
figures are the benchmark's: ``python -m bench load`` prints and records them, docs/reliability.md quotes
them."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
CLIENTS, SECONDS, WARMUP = 10, 20, 8
# Each frame the server publishes turns the body once; a client that keeps up receives each turn in its own
# window. 3/4 is issue 7's 30 updates/s out of the 40 frames/s a crowd of tabs is published (CROWD_HZ).
DELIVERED_MIN = 0.75
FAIR_MIN = 0.75  # the fewest body updates any client received, over the most: no tab starved beside the others


@pytest.mark.slow
def test_ten_clients_each_receive_the_frames_published_for_them(tmp_path):
    out = tmp_path / "load.json"
    proc = subprocess.run([sys.executable, "-m", "bench", "load", "--clients", str(CLIENTS), "--minutes",
                           str(SECONDS / 60), "--warmup", str(WARMUP), "--out", str(out)],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert out.exists(), proc.stderr[-3000:]
    res = json.loads(out.read_text())
    detail = res["clients_detail"]
    assert len(detail) == CLIENTS and all(c["n_errors"] == 0 for c in detail), detail
    rows = res["delivered"]
    assert len(rows) == CLIENTS and {r["client"] for r in rows} == set(range(CLIENTS)), rows  # one session each
    for r in rows:
        assert r["published"] > 0 and r["received"] >= DELIVERED_MIN * r["published"], r
    received = [r["received"] for r in rows]
    assert min(received) >= FAIR_MIN * max(received), rows
    # every session torn down when its client left, and freed: no Session object outlives its tab
    assert res["sessions_opened"] == res["sessions_closed"] == CLIENTS, res
    assert res["sessions_left_at_end"] == 0 and res["live_sessions_after_clients_left"] == 0, res


def test_the_client_decodes_viser_windows():
    """The update counter recognises a body orientation update in viser's wire format, and whose it is."""
    import msgspec
    import zstandard

    from bench.load import _body_moved, _moves_body

    def window(messages):
        inner = msgspec.msgpack.encode({"messages": messages, "timestampSec": 0.0, "binaryBufferLengths": ()})
        packed = zstandard.ZstdCompressor().compress(inner)
        return len(inner).to_bytes(8, "little") + len(packed).to_bytes(8, "little") + packed

    assert _body_moved(window([{"type": "SetOrientationMessage", "name": "/s3/body", "wxyz": [1, 0, 0, 0]}])) == 3
    assert _body_moved(window([{"type": "SetOrientationMessage", "name": "/s12/body", "wxyz": [1, 0, 0, 0]}])) == 12
    assert not _moves_body(window([{"type": "SetOrientationMessage", "name": "/s3/body/mass", "wxyz": [1, 0, 0, 0]}]))
    assert not _moves_body(window([{"type": "SetPositionMessage", "name": "/s3/body", "position": [0, 0, 0]}]))

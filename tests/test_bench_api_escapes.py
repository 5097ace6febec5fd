"""``python -m bench api-escapes`` runs every entry point with every hostile value and writes what it counted; on
this tree nothing escapes the documented error types."""

from __future__ import annotations

import json

import physics
from bench import api_escapes


def test_the_study_counts_every_call_and_finds_no_escape(tmp_path):
    out = tmp_path / "api.json"
    assert api_escapes.main(["--out", str(out), "--note", "test"]) == 0
    record = json.loads(out.read_text())
    counts = record["counts"]
    assert counts["calls"] == len(api_escapes.calls(physics)) * len(api_escapes.HOSTILE)
    assert counts.get("escapes", 0) == 0, record["escapes"][:5]
    assert counts.get("absent", 0) == 0 and counts.get("over the time bound", 0) == 0
    assert counts["calls"] == sum(counts.get(k, 0) for k in ("accepted", "documented error"))
    assert record["machine"]["cpus"] and record["note"] == "test"

"""``python -m bench challenge`` on one start number: its CSV, metadata and chart, and the scripted player within
its bound on every level."""

from __future__ import annotations

import csv
import json
import math

from bench.challenge import FIELDS, main


def test_the_challenge_study_writes_its_rows_meta_and_chart(tmp_path):
    assert main(["--starts", "3", "--reactions", "0.25", "--out", str(tmp_path), "--img", str(tmp_path)]) == 0
    with (tmp_path / "challenge.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert tuple(rows[0]) == FIELDS
    assert sorted(r["level"] for r in rows) == sorted(["rigid", "in_medium", "with_mass", "prolate"])
    for r in rows:
        assert 1.0 < float(r["ratio"]) <= math.sqrt(3)
        assert abs(float(r["score"]) * float(r["ratio"]) - 1.0) < 1e-4  # score = T / T_player, ratio its inverse
        assert 0 < float(r["thrust_s"]) <= float(r["T_player_s"]) + 0.25
    meta = json.loads((tmp_path / "challenge.meta.json").read_text())
    assert meta["command"].startswith("python -m bench challenge --starts 3") and "cores" in meta["machine"]
    assert (tmp_path / "challenge.png").stat().st_size > 10_000

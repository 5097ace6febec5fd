"""Share codes end to end at the edges of the doubles: every number of two presets' scenarios set to 5e-324,
1e308, -1e308, 0, NaN or infinity, written as a code (the TOML as a user could have edited it), decoded, and run
in the tab's engine. Each is either refused by name (the key and its value) or runs with finite readouts; a run
that stops at its start names a value to change. Found two faults: G0 = 5e-324 started at 45 degrees whatever
theta0 said, and a run that faulted at t = 0 did not say which value to change."""

from __future__ import annotations

import base64
import math
import re
import tomllib
import zlib

import pytest

import physics
from app.engine import presets
from app.share import code as share
from app.state import Engine

pytestmark = pytest.mark.filterwarnings("ignore")
EDGES = (5e-324, 1e308, -1e308, 0.0, math.nan, math.inf)
PRESETS = (presets.DEFAULT, "Spherical pendulum damper, resonant")


def _number(v) -> str:
    if isinstance(v, int) or math.isfinite(v):
        return repr(v)
    return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")


def _code(tables: dict) -> str:
    """A share code of these tables, written as TOML by hand: the code a user's own edit could make."""
    lines = []
    for table, body in tables.items():
        lines.append(f"[{table}]")
        for k, v in body.items():
            if isinstance(v, str):
                lines.append(f'{k} = "{v}"')
            elif isinstance(v, list):
                lines.append(f"{k} = [{', '.join(_number(x) for x in v)}]")
            else:
                lines.append(f"{k} = {_number(v)}")
    packed = zlib.compress("\n".join(lines).encode(), 9)
    return share.PREFIX + base64.urlsafe_b64encode(packed).decode().rstrip("=")


def _cases():
    for name in PRESETS:
        tables = tomllib.loads(presets.load_preset(name).to_toml())
        for table, body in tables.items():
            for key, value in body.items():
                if isinstance(value, (int, float)) and not isinstance(value, bool):
                    for edge in EDGES:
                        yield pytest.param(name, table, key, edge, id=f"{name[:8]}-{table}.{key}={edge!r}")


@pytest.mark.parametrize("name", PRESETS)
def test_a_hand_written_code_of_a_preset_is_that_preset(name):
    sc = presets.load_preset(name)
    assert share.decode(_code(tomllib.loads(sc.to_toml()))) == sc


@pytest.mark.parametrize("name,table,key,edge", list(_cases()))
def test_an_edge_value_in_a_shared_code_is_refused_by_name_or_runs(name, table, key, edge):
    tables = tomllib.loads(presets.load_preset(name).to_toml())
    tables[table][key] = edge
    try:
        sc = share.decode(_code(tables))
        # a subnormal G0 keeps too few digits to give theta0 (5e-324 at theta0 = 0.8 started at pi/4): refused
        assert not ((table, key) == ("initial", "G0") and 0 < edge < 1e-308), sc
        eng = Engine(sc)  # the tab's: a scene its run cannot start from is refused, the last scene kept
    except physics.ScenarioError as exc:
        said = str(exc)
        assert "Traceback" not in said
        assert re.match(r"^[\w.\[\] ]+ = ", said), said  # a key (or "share code") and the value it had
        return
    for _ in range(5):
        eng.tick(1 / 30)
    shown = eng.readouts()
    assert math.isfinite(float(shown["theta"].split()[0])), shown
    if eng.run.status == "fault" and eng.run.t == 0.0:
        assert "the most extreme value is" in eng.run.message or "no value is far" in eng.run.message, eng.run.message

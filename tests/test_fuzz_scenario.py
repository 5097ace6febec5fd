"""Property-based fuzzing of scenario parsing and validation (issue 7, "Bad input").

10,000 generated scenarios in all (STRUCTURED + TEXT_EDITS + ARBITRARY_TEXT): valid files with keys set
to wrong types, extreme and non-finite values, keys and tables dropped, unknown keys and tables added;
valid files edited character by character; arbitrary text. Each goes through ``Scenario.from_toml``,
the path every file, upload and CLI argument takes. Nothing may escape but ScenarioError, whose
message is one line naming the parameter, its value and what is allowed. The parser only: no run.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import json
import math
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from physics import Scenario, ScenarioError
from physics.scenario.scenario import _toml_names, sections

SECTIONS = sections()  # every registered table

ROOT = Path(__file__).resolve().parent.parent
TEMPLATE_FILES = sorted((ROOT / "assets" / "scenarios").glob("*.toml")) + [ROOT / "physics" / "data" / "default.toml"]
TEMPLATE_TEXTS = [p.read_text() for p in TEMPLATE_FILES]
TEMPLATES = [tomllib.loads(t) for t in TEMPLATE_TEXTS]
STRUCTURED, TEXT_EDITS, ARBITRARY_TEXT = 5_000, 3_000, 2_000  # 10,000 scenarios
MAX_MESSAGE = 600  # characters: a message a person reads on one line

FUZZ = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
            derandomize=True)  # the same examples in every CI run: a failure reproduces

EXTREMES = [0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1e-300, 1e300, 1.7976931348623157e308,
            -1.7976931348623157e308, math.nan, math.inf, -math.inf, 2**53 + 1, 2**63 - 1, -(2**63), 2**64,
            10**30, -(10**30), 10**400, 10**5000, 1, 0, -1, 3]
WORDS = ["resonant", "optimal", "auto", "full", "averaged", "closed", "K", "Jw", "rest", "quasistatic", "in_plane",
         "meridian_axis", "DOP853", "RK4", "midpoint", "", " ", "nan", "inf", "1.0", "\n", "\"", "\\", "(missing)"]

scalars = st.one_of(
    st.floats(), st.sampled_from(EXTREMES), st.integers(), st.booleans(), st.sampled_from(WORDS),
    st.text(max_size=12), st.dates(), st.datetimes(), st.times(),
)
values = st.one_of(
    scalars,
    st.lists(st.one_of(st.floats(), st.sampled_from(EXTREMES)), max_size=5),
    st.lists(scalars, max_size=4),
    st.dictionaries(st.text(max_size=6), scalars, max_size=3),
    st.lists(st.lists(st.floats(), max_size=3), max_size=3),
)
names = st.one_of(st.text(max_size=10), st.sampled_from(["lambda", "lambda_", "Omega ", "m.m", "B", "dt", "run"]))


# ---- a TOML writer for anything the fuzz builds (tomllib reads, it does not write) ----------------------
def quoted(text: str) -> str:
    """A TOML basic string: JSON's escapes are TOML's, except that TOML also forbids a raw DEL."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v) if v.bit_length() < 10_000 else "1" + "0" * 5000
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, str):
        return quoted(v)
    if isinstance(v, (dt.datetime, dt.date, dt.time)):
        return v.isoformat()
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{quoted(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def to_toml(data: dict) -> str:
    lines = []
    for table, body in data.items():
        if isinstance(body, list) and body and all(isinstance(b, dict) for b in body):
            for b in body:
                lines.append(f"[[{quoted(table)}]]")
                lines += [f"{quoted(k)} = {toml_value(v)}" for k, v in b.items()]
        elif isinstance(body, dict):
            lines.append(f"[{quoted(table)}]")
            lines += [f"{quoted(k)} = {toml_value(v)}" for k, v in body.items()]
        else:
            # a bare value where a table belongs
            lines.insert(0, f"{quoted(table)} = {toml_value(body)}")
    return "\n".join(lines) + "\n"


# ---- the property ---------------------------------------------------------------------------------
def parse(text: str) -> Scenario | ScenarioError:
    """Scenario.from_toml, with every exception but ScenarioError escaping to fail the test."""
    try:
        return Scenario.from_toml(text)
    except ScenarioError as exc:
        assert_clear(exc)
        return exc


def assert_clear(exc: ScenarioError) -> None:
    """One line naming the parameter, the value and what is allowed."""
    msg = str(exc)
    assert isinstance(exc.key, str) and exc.key, msg
    assert isinstance(exc.allowed, str) and exc.allowed.strip(), msg
    assert msg.startswith(f"{exc.key} = ") and msg.endswith(exc.allowed), msg
    assert "\n" not in msg and len(msg) <= MAX_MESSAGE, msg


def assert_sound(sc: Scenario) -> None:
    """An accepted scenario holds only finite numbers and writes out and back to itself."""
    for table, items in sc.to_dict().items():
        for block in items if isinstance(items, list) else [items]:
            for key, v in block.items():
                for x in v if isinstance(v, list) else [v]:
                    assert not isinstance(x, float) or math.isfinite(x), f"{table}.{key} = {x!r}"
    assert Scenario.from_toml(sc.to_toml()) == sc


def known_keys(table: str) -> list[str]:
    return list(_toml_names(table)) if table in SECTIONS else []


@st.composite
def mutated(draw):
    """A template scenario with one to three mutations; returns (data, the single set key or None)."""
    data = json.loads(json.dumps(draw(st.sampled_from(TEMPLATES)), default=str))  # deep copy
    n = draw(st.integers(1, 3))
    target = None
    for _ in range(n):
        kind = draw(st.sampled_from(["set", "set", "set", "set", "unknown_key", "drop_key", "drop_table",
                                     "add_table", "bare_table", "unknown_table"]))
        tables = list(data)
        if kind == "add_table" or not tables:
            name = draw(st.sampled_from(list(SECTIONS)))
            data[name] = {k: draw(values) for k in draw(st.lists(st.sampled_from(known_keys(name)), max_size=4))}
            continue
        if kind == "unknown_table":
            data[draw(names)] = draw(st.dictionaries(names, scalars, max_size=3))
            continue
        table = draw(st.sampled_from(tables))
        if kind == "drop_table":
            del data[table]
            continue
        if kind == "bare_table":
            data[table] = draw(scalars)
            continue
        body = data[table]
        blocks = body if isinstance(body, list) else [body]
        i = draw(st.integers(0, len(blocks) - 1)) if blocks else 0
        block = blocks[i] if blocks else None
        if not isinstance(block, dict):  # a table already replaced by a bare value
            continue
        if kind == "drop_key" and block:
            del block[draw(st.sampled_from(list(block)))]
        elif kind == "unknown_key":
            block[draw(names)] = draw(values)
        elif block:
            key = draw(st.sampled_from(list(block)))
            block[key] = draw(values)
            where = f"{table}[{i}]" if isinstance(body, list) else table
            target = (where, key, block[key]) if n == 1 else None
    return data, target


def _wrong_type_everywhere(v) -> bool:
    """A value no key accepts: not a number, string, list, and not a choice word."""
    return isinstance(v, (bool, dict, dt.date, dt.time))


@pytest.mark.slow
@settings(max_examples=STRUCTURED, **FUZZ)
@given(mutated())
def test_fuzzed_scenario_values_are_accepted_sound_or_rejected_clearly(case):
    data, target = case
    out = parse(to_toml(data))
    if isinstance(out, Scenario):
        assert_sound(out)
        return
    if target is not None and _wrong_type_everywhere(target[2]):
        where, key, value = target
        # the one bad value is the one named (its table's other keys and the other tables are valid)
        assert out.key.startswith(f"{where}.{key}"), (str(out), where, key, value)


@st.composite
def edited_text(draw):
    text = draw(st.sampled_from(TEMPLATE_TEXTS))
    for _ in range(draw(st.integers(1, 5))):
        kind = draw(st.sampled_from(["insert", "delete", "replace_number", "duplicate_line", "truncate"]))
        pos = draw(st.integers(0, len(text)))
        if kind == "insert":
            text = text[:pos] + draw(st.text(alphabet="[]{}=\".,'#\n\\ -+_eE0123456789abcinftrul", min_size=1,
                                             max_size=8) | st.text(min_size=1, max_size=4)) + text[pos:]
        elif kind == "delete":
            text = text[:pos] + text[pos + draw(st.integers(1, 20)):]
        elif kind == "truncate":
            text = text[:pos]
        elif kind == "duplicate_line":
            lines = text.splitlines()
            if lines:
                j = draw(st.integers(0, len(lines) - 1))
                lines.insert(j, lines[j])
                text = "\n".join(lines)
        else:
            import re

            numbers = list(re.finditer(r"(?<![\w.])-?\d+(\.\d+)?([eE][-+]?\d+)?", text))
            if numbers:
                m = draw(st.sampled_from(numbers))
                new = draw(st.sampled_from(["nan", "-inf", "+inf", "1e999", "-1e999", "0", "-0.0", "0x10", "1_000",
                                            "99999999999999999999999", "1e-400", "true", '"1.0"', "[1.0]", "{}",
                                            "1979-05-27", "07:32:00", "5e-324", "1.7976931348623157e308"]))
                text = text[:m.start()] + new + text[m.end():]
    return text


@pytest.mark.slow
@settings(max_examples=TEXT_EDITS, **FUZZ)
@given(edited_text())
def test_edited_scenario_files_are_accepted_sound_or_rejected_clearly(text):
    out = parse(text)
    if isinstance(out, Scenario):
        assert_sound(out)


@pytest.mark.slow
@settings(max_examples=ARBITRARY_TEXT, **FUZZ)
@given(st.one_of(st.text(max_size=200), st.text(alphabet="[]{}=\"'.\n abc0123456789", max_size=200),
                 st.binary(max_size=200).map(lambda b: b.decode("utf-8", "replace"))))
def test_arbitrary_text_is_rejected_clearly(text):
    out = parse(text)
    if isinstance(out, Scenario):
        assert_sound(out)


# ---- cases found by the fuzz, kept as plain tests (fast) ------------------------------------------------
BASE = TEMPLATE_TEXTS[-1]  # the default scene


@pytest.mark.parametrize("text, key, needle", [
    (BASE.replace("m = 0.2", "m = 1" + "0" * 5000), "scenario", "4300 digits"),  # int() refuses it: ValueError
    (BASE + "\n[x]\ny = " + "[" * 50_000 + "]" * 50_000, "scenario", "too deeply"),  # RecursionError
    (BASE.replace("samples = 601", "samples = " + "{a = " * 3000 + "1" + "}" * 3000), "scenario", "too deeply"),
    (BASE.replace("m = 0.2", "m = 1e999"), "mass.m", "finite"),
    (BASE + '\n[""]\n', '""', "unknown table"),  # found by the fuzz: the message's key was empty
    (BASE.replace("[run]", '[run]\n"a\\nb" = 1'), 'run."a\\nb"', "unknown key"),  # a key over two lines
])
def test_found_by_fuzzing_toml(text, key, needle):
    out = parse(text)
    assert isinstance(out, ScenarioError) and out.key == key and needle in str(out)


def test_found_by_fuzzing_huge_integers_from_a_dict():
    data = tomllib.loads(BASE)
    data["body"]["A"] = 10**400  # float() overflows: OverflowError escaped from validation
    with pytest.raises(ScenarioError, match=r"body.A = \(an integer of about 401 digits\): must be a finite"):
        Scenario.from_dict(data)
    data = tomllib.loads(BASE)
    data["run"]["samples"] = 10**5000  # repr() of it raised ValueError while the message was built
    with pytest.raises(ScenarioError, match="run.samples"):
        Scenario.from_dict(data)


def test_found_by_fuzzing_perpendicularity_of_huge_vectors():
    data = {"body": {"A": 1.0, "C": 1.4, "M": 1.0}, "initial": {"G0": 1.0, "theta0": 0.3},
            "run": {"t_end": 1.0}, "plane_pendulum": [{"m": 0.1, "l": 0.2, "k": 1.0, "hinge": [0.0, 0.0, 0.5],
                                                        "axis": [0.0, 0.0, 1e300], "arm": [1e300, 0.0, 1e300]}]}
    # n.e overflowed to inf, the cosine was nan and nan > 1e-9 is False: a skew arm was accepted
    with pytest.raises(ScenarioError, match=r"plane_pendulum\[0\].arm .*perpendicular"):
        Scenario.from_dict(data)


def test_non_text_is_rejected_clearly():
    with pytest.raises(ScenarioError, match="must be TOML text"):
        Scenario.from_toml(BASE.encode())


def test_a_device_file_is_read_only_up_to_the_cap(tmp_path):
    with pytest.raises(ScenarioError, match="at most 1000000 bytes"):  # read_text() of it never returned
        Scenario.load("/dev/zero")
    with pytest.raises(ScenarioError, match="cannot be read"):
        Scenario.load(tmp_path)
    (tmp_path / "bin.toml").write_bytes(b"\xff\xfe[body]")
    with pytest.raises(ScenarioError, match="cannot be read"):
        Scenario.load(tmp_path / "bin.toml")


def test_dataclass_fields_are_all_reachable_from_toml():
    for table, cls in SECTIONS.items():
        assert len(known_keys(table)) == len(dataclasses.fields(cls))

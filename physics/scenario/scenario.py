"""Scenario files: TOML in, validated frozen parameters out, and back to TOML.

A table left out means that part is absent (no mass, no cavity...). Unknown tables and keys are
errors so a typo is never silently ignored. Numbers are written with 17 significant digits, so a
scenario survives a round trip bit for bit.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import stat
import tomllib
from dataclasses import dataclass
from pathlib import Path

from physics import registry
from physics.core.errors import ScenarioError
from physics.scenario.edit import edit_dict
from physics.scenario.params import Body, Initial, Run

BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")  # TOML's bare keys; others are shown quoted
MAX_BYTES = 1_000_000  # a scenario is a few hundred bytes; a cap keeps uploads harmless
# tomllib's cost grows with the square of a dotted key's depth (20,000 levels: 33 s, 1.5 GB), so the
# shape is checked on the raw text before parsing. A scenario's deepest key is table.key (two parts) and
# it has a few dozen keys; these caps leave a wide margin.
MAX_KEY_PARTS = 8  # parts of one dotted key or table header: a.b.c has 3
MAX_KEYS = 2_000  # key/value lines and table headers in one file
MAX_NESTING = 32  # arrays and inline tables inside one another
BOM = "\ufeff"  # a UTF-8 byte-order mark, written by some editors: not part of the TOML
# every scenario's tables (the registry's SHARED_TABLES, which a Param may name); the systems add theirs
BASE = dict(zip(registry.SHARED_TABLES, (Body, Initial, Run), strict=True))


@dataclass(frozen=True)
class _Views:
    """What a Scenario reads of the registry, built once per registry version (``registry.version``): a
    slider change builds a few scenarios, each reading a dozen attributes; without this each read walked every
    system's tables."""

    version: int
    sections: dict[str, type]  # TOML table -> its dataclass: body, the systems' tables, initial, run
    arrays: frozenset[str]  # tables written [[name]]
    absent: dict[str, object]  # Scenario attribute -> its value when the table is absent (None, or () for arrays)
    attribute: dict[str, str]  # TOML table -> Scenario attribute
    owner: dict[str, tuple[registry.System, registry.Table]]  # Scenario attribute -> (system, table)
    systems: dict[str, registry.System]
    default: str | None  # the system a bare body runs
    initial_keys: tuple[tuple[registry.System, str, object], ...]  # (owner, [initial] key, the others' value)
    renamed: dict[str, dict[str, str]]  # table -> {dataclass field: TOML key} where they differ


_VIEWS: _Views | None = None


def _views() -> _Views:
    global _VIEWS
    views = _VIEWS
    if views is not None and views.version == registry.version():
        return views
    pairs = registry.tables()  # loads and checks the registry first
    systems = dict(registry.systems())
    sections = {"body": Body, **{t.name: t.cls for _, t in pairs}, "initial": Initial, "run": Run}
    views = _Views(
        version=registry.version(), sections=sections, arrays=frozenset(t.name for _, t in pairs if t.array),
        absent={t.attribute: () if t.array else None for _, t in pairs},
        attribute={t.name: t.attribute for _, t in pairs}, owner={t.attribute: (s, t) for s, t in pairs},
        systems=systems, default=next((s.name for s in systems.values() if s.default), None),
        initial_keys=tuple((s, k, v) for s in systems.values() for k, v in s.initial_keys.items()),
        renamed={t.name: {f: k for k, f in t.renamed} for _, t in pairs})
    _VIEWS = views
    return views


def sections() -> dict[str, type]:
    """TOML table -> its dataclass: body, every registered system's tables, initial, run."""
    return dict(_views().sections)


def array_tables() -> set[str]:
    return set(_views().arrays)


@dataclass(frozen=True, init=False)
class Scenario:
    """A whole problem: body, the internal part's tables (by its system), initial state and run.

    The systems' tables read as attributes, each named by its Table's ``attribute`` (``sc.mass``, ``sc.cavity``):
    None (an empty tuple for an array table) when absent. ``sc.system`` names the registered system that runs it."""

    body: Body
    initial: Initial
    run: Run
    parts: tuple[tuple[str, object], ...] = ()  # (attribute, value) of the tables present

    def __init__(self, body: Body, initial: Initial, run: Run, **parts):
        views = _views()
        known = views.absent
        for name in parts:
            if name not in known:
                raise ScenarioError(name, "(table)", "unknown part; allowed: " + ", ".join(known))
        present = tuple((name, parts[name]) for name in known if name in parts and parts[name] not in (None, ()))
        object.__setattr__(self, "body", body)
        object.__setattr__(self, "initial", initial)
        object.__setattr__(self, "run", run)
        object.__setattr__(self, "parts", present)
        object.__setattr__(self, "_system", self._find_system(views))
        object.__setattr__(self, "initial", _own_start(initial, views.systems[self._system], views))
        check = views.systems[self._system].check
        if check is not None:
            check(self)

    def __getattr__(self, name: str):
        if name.startswith("__"):
            raise AttributeError(name)
        for attr, value in object.__getattribute__(self, "parts"):
            if attr == name:
                return value
        absent = _views().absent
        if name in absent:
            return absent[name]
        raise AttributeError(f"Scenario has no attribute {name!r}")

    def _find_system(self, views: _Views) -> str:
        """The one system whose tables are present (the default system for a bare body)."""
        owner = views.owner
        chosen = [(owner[a][0], owner[a][1]) for a, _ in self.parts if owner[a][1].selects]
        names = list(dict.fromkeys(s.name for s, _ in chosen))
        if len(names) > 1:
            first, second = chosen[0][1].name, next(t.name for s, t in chosen if s.name != names[0])
            raise ScenarioError(second, "(table)", f"cannot be combined with [{first}]: one internal part at a time")
        if not names:
            names = [owner[self.parts[0][0]][0].name] if self.parts else [views.default]
        for attr, _ in self.parts:
            s, t = owner[attr]
            if s.name != names[0]:
                runs = views.systems[names[0]].label
                raise ScenarioError(t.name, "(table)", f"belongs to the {s.label}, not to the {runs} it runs")
        return names[0]

    @property
    def system(self) -> str:
        """Which registered system runs this scenario."""
        return self._system

    # ---- construction -------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: dict) -> Scenario:
        if not isinstance(data, dict):
            raise ScenarioError("scenario", type(data).__name__, "must be a table of tables")
        views = _views()
        known, arrays, attribute = views.sections, views.arrays, views.attribute
        kwargs = {}
        for table, value in data.items():
            if table not in known:
                raise ScenarioError(_name(table), "(table)", "unknown table; allowed: " + ", ".join(known))
            if table in arrays:
                if isinstance(value, dict):
                    value = [value]
                if not isinstance(value, list) or not value or not all(isinstance(v, dict) for v in value):
                    raise ScenarioError(table, value, f"must be one or more tables [[{table}]]")
                kwargs[attribute[table]] = tuple(_build(table, v, f"{table}[{i}]") for i, v in enumerate(value))
                continue
            if not isinstance(value, dict):
                raise ScenarioError(str(table), value, "must be a table [" + str(table) + "]")
            kwargs[attribute.get(table, table)] = _build(table, value)
        for required in BASE:
            if required not in kwargs:
                raise ScenarioError(required, "(missing)", f"the table [{required}] is required")
        return cls(**kwargs)

    @classmethod
    def from_toml(cls, text: str) -> Scenario:
        if not isinstance(text, str):
            raise ScenarioError("scenario", type(text).__name__, "must be TOML text (str)")
        if len(text) > MAX_BYTES:
            raise ScenarioError("scenario", f"{len(text)} bytes", f"must be at most {MAX_BYTES} bytes")
        text = text.removeprefix(BOM)
        check_shape(text)
        try:
            data = tomllib.loads(text)
        except RecursionError:  # arrays or inline tables nested thousands deep
            raise ScenarioError("scenario", "(TOML)", "nests arrays or inline tables too deeply") from None
        except ValueError as exc:  # TOMLDecodeError, and int() refusing a literal of more than 4300 digits
            nested = _quote_nested_long_integers(text) if "digits" in str(exc) else None
            if nested is not None:  # inside an array or inline table: the wrong type, named with its key below
                return cls.from_toml(nested)
            raise ScenarioError("scenario", "(TOML)", f"is not valid TOML: {exc}") from None
        return cls.from_dict(data)

    @classmethod
    def load(cls, path: str | Path) -> Scenario:
        p = Path(path)
        try:
            data = _read_capped(p)
            if len(data) > MAX_BYTES:
                raise ScenarioError("scenario", p, f"file must be at most {MAX_BYTES} bytes")
            text = data.decode("utf-8-sig")  # a leading byte-order mark is dropped, as the upload does
        except (OSError, UnicodeDecodeError, ValueError) as exc:  # ValueError: a path with a NUL byte
            if isinstance(exc, ScenarioError):
                raise
            why = getattr(exc, "strerror", None) or str(exc)
            raise ScenarioError("scenario", p, f"cannot be read ({why}); give the path of a TOML file") from None
        return cls.from_toml(text)

    # ---- output -------------------------------------------------------------------------
    def to_dict(self) -> dict:
        out = {"body": _items("body", self.body)}
        for _, t in _views().owner.values():
            section = getattr(self, t.attribute)
            if t.array and section:
                out[t.name] = [_items(t.name, s) for s in section]
            elif not t.array and section is not None:
                out[t.name] = _items(t.name, section)
        out["initial"], out["run"] = _items("initial", self.initial), _items("run", self.run)
        return out

    def to_toml(self) -> str:
        lines, arrays = [], array_tables()
        for table, items in self.to_dict().items():
            for block in items if table in arrays else [items]:
                lines.append(f"[[{table}]]" if table in arrays else f"[{table}]")
                lines += [f"{k} = {_toml_value(v)}" for k, v in block.items()]
                lines.append("")
        return "\n".join(lines)

    def replace(self, **changes) -> Scenario:
        """A copy with whole sections replaced (``mass=None`` removes one), validated again."""
        now = dict(body=self.body, initial=self.initial, run=self.run, **dict(self.parts))
        now.update(changes)
        return Scenario(**now)

    def with_values(self, **dotted) -> Scenario:
        """A copy with single keys changed, e.g. ``with_values(**{"mass.m": 0.2})``, validated again (raises
        ScenarioError; how a dotted key maps onto the tables: physics/scenario/edit.py)."""
        data = self.to_dict()
        for key, value in dotted.items():
            edit_dict(data, key, value, self)
        return Scenario.from_dict(data)


def _own_start(initial: Initial, runs: registry.System, views: _Views) -> Initial:
    """``initial`` without the keys another system owns (``System.initial_keys``): a value meaning what this
    system does anyway is dropped, any other refused naming the owner."""
    for owner, key, neutral in views.initial_keys:
        value = getattr(initial, key)
        if owner is runs or value is None:
            continue
        if value != neutral:
            raise ScenarioError(f"initial.{key}", value, f"belongs to the {owner.label}; this scenario runs the "
                                f"{runs.label}, whose part starts at rest relative to the body: leave it out")
        initial = dataclasses.replace(initial, **{key: None})
    return initial


def _read_capped(p: Path) -> bytes:
    """At most MAX_BYTES + 1 bytes of ``p``. Opened without blocking, and a FIFO or socket refused: reading
    one waits for a writer forever; a device such as /dev/zero never ends, so only the cap is read."""
    fd = os.open(p, os.O_RDONLY | os.O_NONBLOCK)
    try:
        mode = os.fstat(fd).st_mode
        if stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):
            raise ScenarioError("scenario", p, "is a pipe or socket, not a file; give the path of a TOML file")
        chunks, size = [], 0
        while size <= MAX_BYTES:
            chunk = os.read(fd, MAX_BYTES + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        return b"".join(chunks)
    finally:
        os.close(fd)


HEADER = re.compile(r"^[ \t]*\[", re.MULTILINE)  # [table] and [[array]] headers
_PART = r"""(?:[A-Za-z0-9_-]++|"[^"\n]*+"|'[^'\n]*+')"""  # possessive: no backtracking over a long word
LONG_KEY = re.compile(rf"(?<![A-Za-z0-9_-]){_PART}(?:[ \t]*+\.[ \t]*+{_PART}){{{MAX_KEY_PARTS},}}")
NESTING = re.compile(r"[\[\]{}\"'#\n]")


def check_shape(text: str) -> None:
    """Refuse, before parsing, TOML whose shape alone would cost more than a scenario can need: too many
    keys, dotted keys with too many parts, arrays or inline tables nested too deeply. '=', dots and
    brackets inside strings or comments may be over-counted; a scenario file is far inside the caps."""
    depth, quote = 0, None
    for m in NESTING.finditer(text):  # brackets outside strings and comments
        c = m.group()
        if quote == "#":
            quote = None if c == "\n" else quote
        elif quote:
            if c == "\n" or c == quote and text[m.start() - 1] != "\\":
                quote = None
        elif c in "\"'#":
            quote = c
        elif c in "[{":
            depth += 1
            if depth > MAX_NESTING:
                raise ScenarioError("scenario", "(TOML)",
                                    f"nests arrays or inline tables too deeply (more than {MAX_NESTING} levels)")
        elif c in "]}":
            depth = max(0, depth - 1)
    keys = text.count("=") + len(HEADER.findall(text))
    if keys > MAX_KEYS:
        raise ScenarioError("scenario", f"{keys} keys", f"must have at most {MAX_KEYS} keys and tables")
    long = LONG_KEY.search(text)
    if long:
        raise ScenarioError("scenario", long.group(), f"a dotted key must have at most {MAX_KEY_PARTS} parts")


LONG_INTEGER = re.compile(r"[0-9][0-9_]{4300,}")  # more digits than int() converts


def _quote_nested_long_integers(text: str) -> str | None:
    """``text`` with each over-long integer inside an array or inline table turned into a string saying so,
    so that parsing goes on and the table key holding it is named; None when one is a key's plain value
    (then the parser's own message, which names the limit, is the clearest)."""
    plain = False

    def quote(m: re.Match) -> str:
        nonlocal plain
        before = text[:m.start()].rstrip(" \t+-")
        line = before[before.rfind("\n") + 1:]
        depth = line.count("[") + line.count("{") - line.count("]") - line.count("}")
        plain = plain or (before.endswith("=") and depth == 0)
        return json.dumps(f"(an integer of {sum(c.isdigit() for c in m.group())} digits)")

    out = LONG_INTEGER.sub(quote, text)
    return None if plain or out == text else out


def _name(key: object) -> str:
    """A key as TOML writes it: bare when it can be, else quoted (an empty or multi-line key stays visible)."""
    text = str(key)
    return text if BARE_KEY.fullmatch(text) else json.dumps(text)


def _toml_names(table: str) -> dict[str, str]:
    """TOML key -> dataclass field of one table."""
    views = _views()
    back = views.renamed.get(table, {})
    return {back.get(f.name, f.name): f.name for f in dataclasses.fields(views.sections[table])}


def _items(table: str, section) -> dict:
    back = {f: k for k, f in _toml_names(table).items()}
    items = {}
    for f in dataclasses.fields(section):
        value = getattr(section, f.name)
        if value is not None:
            items[back[f.name]] = list(value) if isinstance(value, tuple) else value
    return items


def _build(table: str, values: dict, where: str | None = None):
    where = where or table
    cls = _views().sections[table]
    names = _toml_names(table)
    kwargs = {}
    for key, value in values.items():
        if key not in names:
            raise ScenarioError(f"{where}.{_name(key)}", value, "unknown key; allowed: " + ", ".join(names))
        kwargs[names[key]] = value
    required = [k for k, f in names.items()
                if next(x for x in dataclasses.fields(cls) if x.name == f).default is dataclasses.MISSING]
    for key in required:
        if key not in values:
            raise ScenarioError(f"{where}.{key}", "(missing)", "is required")
    try:
        return cls(**kwargs)
    except ScenarioError as exc:
        if where != table and exc.key.startswith(table):  # name which pendulum: plane_pendulum[2].arm
            raise ScenarioError(where + exc.key[len(table):], exc.value, exc.allowed) from None
        raise


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v) or math.isinf(v):  # never produced by a validated scenario
            raise ValueError(v)
        return repr(v) if "e" in repr(v) or "." in repr(v) else repr(v) + ".0"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(type(v))

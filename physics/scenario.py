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

from .errors import ScenarioError
from .params import RENAMED, Body, Cavity, Control, Initial, Mass, Medium, Run
from .params_pendulum import Pendulum, PlanePendulum

SECTIONS = {"body": Body, "mass": Mass, "pendulum": Pendulum, "plane_pendulum": PlanePendulum, "cavity": Cavity,
            "medium": Medium, "control": Control, "initial": Initial, "run": Run}
ARRAY_TABLES = {"plane_pendulum"}  # written [[plane_pendulum]], one table per pendulum
FIELD = {"plane_pendulum": "plane_pendulums"}  # table name -> Scenario attribute where they differ

BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")  # TOML's bare keys; others are shown quoted
MAX_BYTES = 1_000_000  # a scenario is a few hundred bytes; a cap keeps uploads harmless
# tomllib's cost grows with the square of a dotted key's depth (20,000 levels: 33 s, 1.5 GB), so the
# shape is checked on the raw text before parsing. A scenario's deepest key is table.key (two parts) and
# it has a few dozen keys; these caps leave a wide margin.
MAX_KEY_PARTS = 8  # parts of one dotted key or table header: a.b.c has 3
MAX_KEYS = 2_000  # key/value lines and table headers in one file
MAX_PLANE_PENDULUMS = 24  # a ring damper has a handful; each one adds 2 states and a rigid-body coupling
MAX_NESTING = 32  # arrays and inline tables inside one another
BOM = "\ufeff"  # a UTF-8 byte-order mark, written by some editors: not part of the TOML


@dataclass(frozen=True)
class Scenario:
    """A whole problem: body, optional internal parts and torques, initial state and run."""

    body: Body
    initial: Initial
    run: Run
    mass: Mass | None = None
    pendulum: Pendulum | None = None
    plane_pendulums: tuple[PlanePendulum, ...] = ()
    cavity: Cavity | None = None
    medium: Medium | None = None
    control: Control | None = None

    def __post_init__(self):
        if self.mass is not None and self.mass.m >= self.body.M:
            raise ScenarioError("mass.m", self.mass.m,
                                f"must be less than body.M = {self.body.M:g} (M is the total mass)")
        for where, bob, place, reach in _bob_reaches(self):  # the bobs' moments about O must be finite numbers
            if not math.isfinite(bob.m * reach * reach):
                field = "l" if bob.l >= reach / 2 else place
                raise ScenarioError(f"{where}.{field}", getattr(bob, field), "is too large: the bob's moment about "
                                    f"O, m (|r| + l)^2 = {bob.m:.3g} * ({reach:.3g})^2, must stay finite")
        if len(self.plane_pendulums) > MAX_PLANE_PENDULUMS:
            raise ScenarioError("plane_pendulum", f"{len(self.plane_pendulums)} tables",
                                f"at most {MAX_PLANE_PENDULUMS} plane pendulums (a damper has a few; 200 made each "
                                "frame of the explorer take seconds)")
        parts = [name for name, present in (("mass", self.mass is not None), ("pendulum", self.pendulum is not None),
                                            ("plane_pendulum", bool(self.plane_pendulums))) if present]
        if len(parts) > 1:
            raise ScenarioError(parts[1], "(table)",
                                f"cannot be combined with [{parts[0]}]: one internal part at a time")
        bobs = ([self.pendulum] if self.pendulum else []) + list(self.plane_pendulums)
        if bobs:
            total = sum(b.m for b in bobs)
            if total >= self.body.M:
                raise ScenarioError(parts[0] + ".m", total, f"(all bobs) must be less than body.M = {self.body.M:g}")
            for extra in ("cavity", "medium", "control"):
                if getattr(self, extra) is not None:
                    raise ScenarioError(extra, "(table)", "is not supported together with pendulum dampers")
            if self.initial.mass_state != "rest":
                raise ScenarioError("initial.mass_state", self.initial.mass_state,
                                    'must be "rest" with pendulum dampers: the bobs start at rest relative to the body')

    @property
    def system(self) -> str:
        """Which registered system runs this scenario."""
        if self.pendulum is not None:
            return "spherical_pendulum"
        if self.plane_pendulums:
            return "plane_pendulums"
        return "moving_mass"

    # ---- construction -------------------------------------------------------------------
    @classmethod
    def from_dict(cls, data: dict) -> Scenario:
        if not isinstance(data, dict):
            raise ScenarioError("scenario", type(data).__name__, "must be a table of tables")
        kwargs = {}
        for table, value in data.items():
            if table not in SECTIONS:
                raise ScenarioError(_name(table), "(table)", "unknown table; allowed: " + ", ".join(SECTIONS))
            if table in ARRAY_TABLES:
                if isinstance(value, dict):
                    value = [value]
                if not isinstance(value, list) or not value or not all(isinstance(v, dict) for v in value):
                    raise ScenarioError(table, value, f"must be one or more tables [[{table}]]")
                kwargs[FIELD[table]] = tuple(_build(table, v, f"{table}[{i}]") for i, v in enumerate(value))
                continue
            if not isinstance(value, dict):
                raise ScenarioError(str(table), value, "must be a table [" + str(table) + "]")
            kwargs[table] = _build(table, value)
        for required in ("body", "initial", "run"):
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
                raise ScenarioError("scenario", str(p), f"file must be at most {MAX_BYTES} bytes")
            text = data.decode("utf-8-sig")  # a leading byte-order mark is dropped, as the upload does
        except (OSError, UnicodeDecodeError, ValueError) as exc:  # ValueError: a path with a NUL byte
            if isinstance(exc, ScenarioError):
                raise
            why = getattr(exc, "strerror", None) or str(exc)
            raise ScenarioError("scenario", str(p), f"cannot be read ({why}); give the path of a TOML file") from None
        return cls.from_toml(text)

    # ---- output -------------------------------------------------------------------------
    def to_dict(self) -> dict:
        out = {}
        for table in SECTIONS:
            section = getattr(self, FIELD.get(table, table))
            if table in ARRAY_TABLES:
                if section:
                    out[table] = [_items(table, s) for s in section]
            elif section is not None:
                out[table] = _items(table, section)
        return out

    def to_toml(self) -> str:
        lines = []
        for table, items in self.to_dict().items():
            for block in items if table in ARRAY_TABLES else [items]:
                lines.append(f"[[{table}]]" if table in ARRAY_TABLES else f"[{table}]")
                lines += [f"{k} = {_toml_value(v)}" for k, v in block.items()]
                lines.append("")
        return "\n".join(lines)

    def replace(self, **changes) -> Scenario:
        """A copy with whole sections replaced, validated again."""
        return dataclasses.replace(self, **changes)

    def with_values(self, **dotted) -> Scenario:
        """A copy with single keys changed, e.g. ``with_values(**{"mass.m": 0.2})``."""
        data = self.to_dict()
        for path, value in dotted.items():
            table, _, key = path.partition(".")
            data.setdefault(table, {})[key] = value
            if table == "initial" and key == "omega":
                data["initial"].pop("G0", None), data["initial"].pop("theta0", None)
            if table == "initial" and key in ("G0", "theta0"):
                data["initial"].pop("omega", None)
        return Scenario.from_dict(data)


def _bob_reaches(sc: Scenario):
    """(key prefix, bob, the key placing its pivot, a bound |pivot| + l on its distance from O) per pendulum."""
    if sc.pendulum is not None:
        yield "pendulum", sc.pendulum, "h", abs(sc.pendulum.h) + sc.pendulum.l
    for i, pp in enumerate(sc.plane_pendulums):
        if pp.preset is None:
            yield f"plane_pendulum[{i}]", pp, "hinge", max(abs(x) for x in pp.hinge) * math.sqrt(3.0) + pp.l
        else:
            yield f"plane_pendulum[{i}]", pp, "R" if pp.R >= abs(pp.z_p) else "z_p", pp.R + abs(pp.z_p) + pp.l


def _read_capped(p: Path) -> bytes:
    """At most MAX_BYTES + 1 bytes of ``p``. Opened without blocking, and a FIFO or socket refused: reading
    one waits for a writer forever; a device such as /dev/zero never ends, so only the cap is read."""
    fd = os.open(p, os.O_RDONLY | os.O_NONBLOCK)
    try:
        mode = os.fstat(fd).st_mode
        if stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):
            raise ScenarioError("scenario", str(p), "is a pipe or socket, not a file; give the path of a TOML file")
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
    fields = [f.name for f in dataclasses.fields(SECTIONS[table])]
    back = {name: key for (t, key), name in RENAMED.items() if t == table}
    return {back.get(f, f): f for f in fields}


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
    cls = SECTIONS[table]
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

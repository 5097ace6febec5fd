"""Scenario files: TOML in, validated frozen parameters out, and back to TOML.

A table left out means that part is absent (no mass, no cavity...). Unknown tables and keys are
errors so a typo is never silently ignored. Numbers are written with 17 significant digits, so a
scenario survives a round trip bit for bit.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
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
        try:
            data = tomllib.loads(text)
        except RecursionError:  # arrays or inline tables nested thousands deep
            raise ScenarioError("scenario", "(TOML)", "nests arrays or inline tables too deeply") from None
        except ValueError as exc:  # TOMLDecodeError, and int() refusing a literal of more than 4300 digits
            raise ScenarioError("scenario", "(TOML)", f"is not valid TOML: {exc}") from None
        return cls.from_dict(data)

    @classmethod
    def load(cls, path: str | Path) -> Scenario:
        p = Path(path)
        try:
            with p.open("rb") as f:  # read at most the cap: a device such as /dev/zero never ends
                data = f.read(MAX_BYTES + 1)
            if len(data) > MAX_BYTES:
                raise ScenarioError("scenario", str(p), f"file must be at most {MAX_BYTES} bytes")
            text = data.decode("utf-8")
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

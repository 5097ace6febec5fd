"""Generated scenario files for the end-to-end fuzz (tests/test_fuzz_end_to_end.py), from a seeded generator.

Every numeric key of every shipped scenario (vector components too) gets, in turn, a magnitude from
5e-324 to 1e308; more examples change several keys at once, ask for huge sample counts, tiny fixed steps
or long horizons, and nest dotted keys up to thousands deep. Same seed, same files: a failure reproduces.
"""

from __future__ import annotations

import json
import math
import random
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TEMPLATE_FILES = sorted((ROOT / "assets" / "scenarios").glob("*.toml")) + [ROOT / "physics" / "data" / "default.toml"]
MAGNITUDES = [5e-324, 2.2250738585072014e-308, 1e-300, 1e-200, 1e-100, 1e-30, 1e-8, 1e-3, 1.0, 1e3, 1e8, 1e30,
              1e100, 1e200, 1e300, 1e308, 1.7976931348623157e308]
SAMPLES = [2, 3, 1_000, 100_000, 1_000_000, 10_000_000]


def templates() -> list[dict]:
    return [tomllib.loads(p.read_text()) for p in TEMPLATE_FILES]


def numeric_paths(data: dict) -> list[tuple]:
    """Paths (table, index or None, key, component or None) of every number in a scenario dict."""
    out = []
    for table, items in data.items():
        blocks = list(enumerate(items)) if isinstance(items, list) else [(None, items)]
        for i, block in blocks:
            for key, value in block.items():
                if isinstance(value, bool):
                    continue
                if isinstance(value, (int, float)):
                    out.append((table, i, key, None))
                elif isinstance(value, list):
                    out += [(table, i, key, j) for j, x in enumerate(value) if isinstance(x, (int, float))]
    return out


def put(data: dict, path: tuple, value) -> None:
    table, i, key, j = path
    block = data[table] if i is None else data[table][i]
    if j is None:
        block[key] = value
    else:
        block[key][j] = value


def _value(rng: random.Random, old) -> float | int:
    x = rng.choice(MAGNITUDES) if rng.random() < 0.7 else 10 ** rng.uniform(-323, 308)
    if isinstance(old, int) and not isinstance(old, bool) and x >= 1 and rng.random() < 0.3:
        return int(min(x, 1e18))
    return -x if rng.random() < 0.15 else x


def to_toml(data: dict, extra: str = "") -> str:
    """A TOML text of a scenario dict (tomllib reads, it does not write). ``extra`` goes into [run]."""
    def val(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, float):
            return repr(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))
        if isinstance(v, int):
            return str(v)
        if isinstance(v, str):
            return json.dumps(v)
        return "[" + ", ".join(val(x) for x in v) + "]"

    lines = []
    for table, items in data.items():
        for block in items if isinstance(items, list) else [items]:
            lines.append(f"[[{table}]]" if isinstance(items, list) else f"[{table}]")
            lines += [f"{k} = {val(v)}" for k, v in block.items()]
            if table == "run" and extra:
                lines.append(extra)
            lines.append("")
    return "\n".join(lines)


def generate(seed: int = 17, extra_random: int = 60) -> list[tuple[str, str]]:
    """(label, TOML text) pairs: one per numeric key of every template, then ``extra_random`` mixtures."""
    rng = random.Random(seed)
    bases = templates()
    out = []
    k = 0
    for n, base in enumerate(bases):
        for path in numeric_paths(base):
            data = json.loads(json.dumps(base))
            value = MAGNITUDES[k % len(MAGNITUDES)]
            k += 1
            put(data, path, value)
            data["run"]["samples"] = 11  # the key's effect, not the output size, is under test here
            out.append((f"t{n}:{path}={value!r}", to_toml(data)))
    # the same keys again at fidelity closed on the moving-mass templates: a closed form integrates its own slow
    # equation (seed 004 eq. (13)) with scipy, outside the run's step budget, where an overflowing right side once
    # looped for good (body.C = 1e-300 on quadratic_friction); the templates themselves run auto or full
    for n, base in enumerate(bases):
        if "mass" not in base or base["run"].get("fidelity") == "closed":
            continue
        for path in numeric_paths(base):
            data = json.loads(json.dumps(base))
            value = MAGNITUDES[k % len(MAGNITUDES)]
            k += 1
            put(data, path, value)
            data["run"].update(samples=11, fidelity="closed")
            out.append((f"closed t{n}:{path}={value!r}", to_toml(data)))
    fidelities = random.Random(seed + 1)  # its own stream: the mixtures' other draws stay what they were
    for m in range(extra_random):
        data = json.loads(json.dumps(rng.choice(bases)))
        paths = numeric_paths(data)
        for path in rng.sample(paths, min(len(paths), rng.randint(1, 4))):
            table, i, key, j = path
            block = data[table] if i is None else data[table][i]
            put(data, path, _value(rng, block[key] if j is None else block[key][j]))
        run, extra = data["run"], ""
        kind = rng.random()
        if kind < 0.2:
            run["samples"] = rng.choice(SAMPLES)
            run.pop("t_eval", None)
        elif kind < 0.3:
            run.update(method=rng.choice(["RK4", "RK8", "midpoint"]), dt=rng.choice([1e-12, 1e-6, 1e-3]))
        elif kind < 0.4:
            run["t_end"] = rng.choice([1e6, 1e9, 1e300])
            run.pop("t_eval", None)
        elif kind < 0.5:
            extra = ".".join(["a"] * rng.choice([3, 9, 50, 2_000, 20_000])) + " = 1"
        elif kind < 0.55:
            run["method"] = rng.choice(["RK45", "Radau", "LSODA"])
        run.pop("dt", None) if run.get("method") not in ("RK4", "RK8", "midpoint") else None
        if fidelities.random() < 0.5:  # every model, not only the one each template names
            run["fidelity"] = fidelities.choice(["auto", "full", "averaged", "closed"])
        out.append((f"mix{m}", to_toml(data, extra)))
    return out

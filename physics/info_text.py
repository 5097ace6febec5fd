"""What ``python -m physics info`` prints: each derived quantity with its unit and a short meaning.

Text for people (6 significant digits, one ``name = value unit  meaning`` line each) and JSON for
programs (every float to full precision; inf and nan, which JSON lacks, as the strings "inf", "nan").
Names and equations are those of docs/models.md and physics/systems/derived.py; each system declares the
units and meanings of its own quantities (``System.quantities``, ``System.quantity``).
"""

from __future__ import annotations

import json
import math

from physics.registry import systems
from physics.systems.choice import DEFAULT_ACCURACY

# name -> (unit, meaning) of what physics/systems/derived.py adds for every system
COMMON = {
    "auto_fidelity": ("", "the fidelity run.fidelity = \"auto\" picks"),
    "auto_model": ("", "the model it runs"),
    "auto_method": ("", "the integrator it uses"),
    "auto_accuracy": ("rad", f"run.accuracy asked for (not set: auto asks {DEFAULT_ACCURACY:g} rad)"),
    "averaged_error_bound": ("rad", "max |theta - theta_full| the averaged model stays within (inf: no claim)"),
    "closed_error_bound": ("rad", "max |theta - theta_full| the closed form stays within (inf: no claim)"),
    "auto_error_bound": ("rad", "that estimate for auto's choice (0: the full model, the reference)"),
    "error_bound_method": ("", "how the estimates were obtained"),
    "auto_reason": ("", ""),  # a sentence already
}


def describe(name: str, system: str) -> tuple[str, str]:
    """(unit, meaning) of a derived quantity of ``system`` (its name); ("", "") when it has none on record."""
    owner = systems().get(system)
    if owner is not None and name in owner.quantities:
        return owner.quantities[name]
    if name in COMMON:
        return COMMON[name]
    described = owner.quantity(name) if owner is not None else None
    return described if described is not None else ("", "")


def readable(value) -> str:
    """6 significant digits for a float, the text itself otherwise."""
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def text_lines(values: dict, system: str) -> list[str]:
    """One ``name = value unit  meaning`` line per quantity, aligned."""
    width = max((len(k) for k in values), default=0)
    shown = {k: readable(v) for k, v in values.items()}
    vwidth = min(max((len(v) for k, v in shown.items() if k != "auto_reason"), default=0), 14)
    lines = []
    for k, v in shown.items():
        unit, meaning = describe(k, system)
        tail = f"{unit:<12}  {meaning}" if unit else meaning
        lines.append(f"{k:<{width}} = {v:<{vwidth}}  {tail}".rstrip())
    return lines


def as_json(values: dict, system: str) -> str:
    """Every quantity with its unit and meaning; floats to full precision (JSON numbers round-trip)."""
    def number(v):
        if isinstance(v, float):
            return float(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))
        return v

    out = {k: {"value": number(v), "unit": describe(k, system)[0], "meaning": describe(k, system)[1]}
           for k, v in values.items()}
    return json.dumps(out, indent=1, allow_nan=False)

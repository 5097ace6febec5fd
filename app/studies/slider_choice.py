"""The study panels' parameter lists: which sliders a sweep or a design can vary in a scene, named as the panel's
sliders are ("m (kg)", "spring k (N m/rad)"), and the slider key a chosen name stands for.

The sweep and design panels named their options by slider key ("mass.m", "pendulum.c_d"), the compare panel and the
sliders by text: one parameter under two names on one page. A raw client can send any text as a dropdown's value,
so ``key_of`` answers None for a name the scene's system does not offer, and the panel says so.
"""

from __future__ import annotations

import physics

from ..engine import controls
from .sweep_ranges import scenario_key

NONE = "(none)"


def sweepable(sc: physics.Scenario) -> list[str]:
    """The slider keys (controls.PARAMS) of this scenario's system that a sweep or a design can vary in it."""
    allowed = set(physics.numeric_keys(sc))
    return [p.key for p in controls.PARAMS if sc.system in p.systems and scenario_key(p.key, sc.system) in allowed]


def names(system: str) -> dict[str, str]:
    """Option text -> slider key for ``system``'s sliders: the slider's own text, with its key added where two
    would read alike."""
    keys = [p.key for p in controls.PARAMS if system in p.systems]
    texts = [controls.BY_KEY[k].text for k in keys]
    return {(t if texts.count(t) == 1 else f"{t} [{k}]"): k for t, k in zip(texts, keys, strict=True)}


def options(sc: physics.Scenario, optional: bool) -> list[str]:
    """The option texts of a parameter dropdown for ``sc`` (its ``sweepable`` sliders); NONE first when the
    parameter is ``optional``, and NONE alone when nothing can be varied."""
    keys = set(sweepable(sc))
    texts = [t for t, k in names(sc.system).items() if k in keys]
    return [NONE, *texts] if optional or not texts else texts


def key_of(text: str, system: str) -> str | None:
    """The slider key an option ``text`` names for ``system``; None for NONE or a text not offered."""
    return names(system).get(text) if isinstance(text, str) else None


def text_of(key: str, system: str) -> str:
    """The option text of the slider ``key`` for ``system``."""
    return next((t for t, k in names(system).items() if k == key), key)


def slider_map(system: str) -> dict[str, str]:
    """Scenario key -> the slider that sets it, for this system's sliders."""
    return {scenario_key(p.key, system): p.key for p in controls.PARAMS if system in p.systems}


def scenario_text(dotted: str, system: str) -> str:
    """The text of the slider that sets the scenario key ``dotted`` in ``system`` ("mass.m" -> "m (kg)"), for a
    chart's axis; the key itself where no slider sets it (a sweep run from a file may vary any numeric key)."""
    slider = slider_map(system).get(dotted)
    return dotted if slider is None else text_of(slider, system)


def offer(dropdown, texts: list[str]) -> None:
    """Give ``dropdown`` the options ``texts``, keeping its choice where it is still offered (else the first)."""
    if list(dropdown.options) != texts:
        dropdown.options = texts
    if dropdown.value not in texts:
        dropdown.value = texts[0]

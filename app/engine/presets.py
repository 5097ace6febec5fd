"""The explorer's presets: the built-in default, the scenario files in assets/scenarios, a few
scenes that have no file (pendulum dampers, braking, the intermediate-axis flip), and one
representative run of each reproduced figure (assets/scenarios/figures, written by
``python -m bench figures --presets``; each file's first line ``# preset: TITLE`` gives its title)."""

from __future__ import annotations

from pathlib import Path

import physics

ASSETS = Path(__file__).resolve().parents[2] / "assets" / "scenarios"
FIGURES = ASSETS / "figures"
EXPLORER = ASSETS / "explorer"  # the explorer's own scenes, offered after the files above and before the examples
TITLE_LINE = "# preset: "  # the first line of a preset file: its title (bench/figures.py PRESET_HEADER writes it too)
DEFAULT = "Default: oblate body settling (1 min)"

# Scenes without a file. Each is a scenario dict in the TOML layout (README "Use"). The systems' examples
# (physics.System.example, titled by their first line) are presets too: see examples().
def _title(path: Path) -> str:
    """A scenario file's title: its first line ``# preset: TITLE``, else its name."""
    with path.open(encoding="utf-8") as fh:
        first = fh.readline().strip()
    return first[len(TITLE_LINE):].strip() if first.startswith(TITLE_LINE) else path.stem


def _text_title(text: str) -> str | None:
    first = text.partition("\n")[0].strip()
    return first[len(TITLE_LINE):].strip() if first.startswith(TITLE_LINE) else None


def examples() -> dict[str, str]:
    """Title -> TOML text of every registered system's example that has a title line (the default system's
    example is the default scene, DEFAULT)."""
    return {title: s.example for s in physics.SYSTEMS.values() if (title := _text_title(s.example))}


FIGURE_ORDER = ("seed000", "seed004", "seed002")  # docs/figures.md's order


def _figure_order(f: Path) -> tuple[int, str]:
    return next((i for i, p in enumerate(FIGURE_ORDER) if f.stem.startswith(p)), len(FIGURE_ORDER)), f.stem


def preset_files() -> dict[str, Path]:
    """Title -> scenario file: assets/scenarios/*.toml, the explorer's own scenes (assets/scenarios/explorer, in
    their files' order), then the figure presets in the order bench wrote them."""
    files = sorted(ASSETS.glob("*.toml")) if ASSETS.is_dir() else []
    if EXPLORER.is_dir():
        files += sorted(EXPLORER.glob("*.toml"))
    if FIGURES.is_dir():
        files += sorted(FIGURES.glob("*.toml"), key=_figure_order)
    return {_title(f): f for f in files}


def preset_names() -> list[str]:
    """Each title once: a system's example that is also shipped as a file (so that ``python -m physics run``
    has it) is one preset, not two (a dropdown with a repeated option does not open on the page)."""
    files = preset_files()
    figures = [t for t, f in files.items() if f.parent == FIGURES]
    own = [t for t, f in files.items() if f.parent == EXPLORER]
    names = [DEFAULT] + [t for t in files if t not in figures + own] + own + list(examples()) + figures
    return list(dict.fromkeys(names))


def load_preset(name: str) -> physics.Scenario:
    """The scenario of a preset (ScenarioError if it no longer validates, KeyError if unknown)."""
    if name == DEFAULT:
        return physics.default_scenario()
    if name in (shown := examples()):
        return physics.Scenario.from_toml(shown[name])
    return physics.Scenario.load(preset_files()[name])


WARP_MIN, WARP_MAX = 0.1, 1e4
PLAY_SECONDS = 40.0  # a preset's suggested warp plays its whole run in about this long


def suggested_warp(sc: physics.Scenario) -> float:
    """A warp that shows the preset's whole run in about PLAY_SECONDS, never below 1x."""
    return float(min(WARP_MAX, max(1.0, sc.run.t_end / PLAY_SECONDS)))


# The cheaper fidelity a preset's figure compares the full model with: choosing the preset turns that overlay
# on (file stem -> overlay). The braking figures and seed 004's counterparts are closed forms; the pendulum
# frequency and resonance figures, linear theory's envelope (the "closed" overlay of a pendulum system).
OVERLAYS = {
    "seed000_fig1a_prolate": "closed", "seed000_fig1b_oblate": "closed",
    **{f"seed004_fig{f}_{shape}": "closed" for f in (1, 2, 3, 4) for shape in ("oblate", "prolate")},
    "seed002_frequencies_set_R": "closed", "seed002_resonance_detuned": "closed",
    "seed002_averaged_eps025": "averaged",
}


def overlay_of(name: str) -> str | None:
    """The overlay a preset names ("averaged" or "closed"), or None when it names none."""
    path = preset_files().get(name)
    return OVERLAYS.get(path.stem) if path is not None else None


# What choosing a system starts from: its example scenario (physics.System.example; the moving mass's is the
# default scene), named by its title line; the body and the initial state are the current scene's where
# they fit (system_scenes).
def system_template(system: str) -> tuple[physics.Scenario, str]:
    """The example scenario of ``system`` and the name the panel shows for it."""
    if not isinstance(system, str) or system not in physics.SYSTEMS:  # a list from a raw client is unhashable
        raise physics.ScenarioError("system", system, f"is not one of {', '.join(physics.SYSTEMS)}")
    spec = physics.SYSTEMS[system]
    template = physics.Scenario.from_toml(spec.example)
    if template == physics.default_scenario():
        return template, DEFAULT
    return template, _text_title(spec.example) or f"{spec.label} example"


def _with_start(data: dict) -> physics.Scenario:
    """The scenario of ``data``; a start the system refuses (a quasi-static start for a part that starts at
    rest) falls back to its default."""
    try:
        return physics.Scenario.from_dict(data)
    except physics.ScenarioError as exc:
        if exc.key != "initial.mass_state" or "mass_state" not in data["initial"]:
            raise
        data["initial"].pop("mass_state")
        return physics.Scenario.from_dict(data)


def system_scenes(current: physics.Scenario, system: str) -> list[tuple[physics.Scenario, str]]:
    """Scenes of ``system`` to try in turn, each (scenario, the name the panel shows): the template's internal
    part with the current body (A, B, C, M) and initial state (G0 and theta0, or omega); then the same with the
    template's spring as a number (a prolate body has no resonant spring); then the template as it is. Some
    refusals come only when a run starts (the resonant spring), so the engine tries them."""
    template, name = system_template(system)
    data = template.to_dict()
    now = current.to_dict()
    data["body"] = now["body"]
    data["initial"] = dict(now["initial"])
    out = []
    try:
        out.append((_with_start(data), f"{name}, body kept"))
        resolved = physics.get_system(system).values(template)
        words = [(t, k) for t, table in data.items() if isinstance(table, dict)
                 for k, v in table.items() if isinstance(v, str) and f"{t}.{k}" in resolved]
        if words:  # a value in words (a resonant spring): the template's, as the number it resolves to
            for t, k in words:
                data[t][k] = float(resolved[f"{t}.{k}"])
            out.append((_with_start(data), f"{name}, body kept"))
    except physics.ScenarioError:
        pass
    return out + [(template, name)]

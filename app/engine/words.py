"""The panel's words: what the explorer says to a class, in the physics' terms rather than the papers'
numbering. The papers' symbols stay where they help (m, rho, Omega, chi, lambda, b, K, theta); formulas,
model names and the attitude quaternion go to the "Details" folder, one click away.

Plain Python (no viser): the readouts, the auto badge's two halves and the status line's wording.
"""

from __future__ import annotations

import math
import re

import physics

FIDELITY_WORDS = {
    "full": "every moving part integrated",
    "averaged": "the quasi-rigid (averaged) model",
    "closed": "a closed-form solution",
}


# a paper's equation number in physics' sentences, "(seed 000 (2.11))": the Details folder keeps it
PAPER_REF = re.compile(r"\s*\(seed \d+[^()]*(\([^()]*\))?[^()]*\)")


def condition_words(c) -> str:
    """What a validity condition (physics' Condition) means for the motion: the system's own sentence (every
    condition has one: tests/test_figure_battery.py), its formula only if a system left it out."""
    return c.sentence or c.name


def condition_line(c) -> str:
    """One line of the badge: a condition met, "✓ the spring is fast next to the spin", or not, "✗ the spring is
    fast next to the spin: not here (eps = |w0|/Omega = 0.52 > 0.2)": the requirement said once, as it is, and
    whether this scene meets it (never "fails: ... is light", which reads as a double negative)."""
    return f"✓ {condition_words(c)}" if c.holds else f"✗ {condition_words(c)}: not here ({c})"


def reason_words(reason: str, conds: list) -> str:
    """Auto's reason (physics' sentence, which quotes the conditions' formulas) in words; once the badge
    has listed the conditions, only what the sentence adds to them ("closed form exists")."""
    if conds and reason.startswith(("averaged conditions fail", "conditions fail")):
        return ""  # the badge's ✗ lines say which: the same conditions (physics.validity_conditions)
    if conds and reason.startswith("averaged conditions hold"):
        reason = reason.rpartition("; ")[2] if "; " in reason else ""
    for c in conds:
        reason = reason.replace(str(c), condition_words(c))
    return PAPER_REF.sub("", reason)


def estimate_words(d: dict) -> list[str]:
    """One line per cheaper model with an error estimate in ``physics.derived`` (``d``): how far its theta stays
    from the full model's over the run, or that it makes no claim here (inf)."""
    out = []
    for fid in ("closed", "averaged"):
        value = d.get(f"{fid}_error_bound")
        if not isinstance(value, float):
            continue
        if not math.isfinite(value):
            out.append(f"{fid}: no error estimate for this scene (outside what it was measured on)")
        elif value >= math.pi:  # capped: theta is in [0, pi], so the estimate holds and says nothing
            out.append(f"{fid}: no useful estimate for this scene (it allows any theta)")
        else:
            out.append(f"{fid}: within {value:.2g} rad of the full model over the run")
    return out


def badge_parts(d: dict, conds: list, chosen: str = "auto") -> tuple[str, str]:
    """Auto's badge from ``physics.derived`` (``d``) and ``physics.validity_conditions`` (``conds``):
    (what the panel shows, in words; the formulas with their values, for the Details folder). ``chosen``: the
    scene's fidelity. Where it is not auto (the default scene and the figures' presets run the full model), the
    badge says what auto would run: "auto → full" under Fidelity "full" read as if auto were running."""
    if chosen == "auto":
        head = f"**auto → {d['auto_fidelity']}** · {d.get('auto_method', '')}"
    else:
        head = f"**{chosen}** as chosen; auto would run **{d['auto_fidelity']}** · {d.get('auto_method', '')}"
    asked = d.get("auto_accuracy", "not set")
    lines = [f"accuracy asked: {asked:g} rad" if isinstance(asked, float)
             else f"accuracy asked: {physics.DEFAULT_ACCURACY:g} rad (the default)"]
    lines += estimate_words(d)
    if conds:
        unmet = sum(not c.holds for c in conds)
        lines.append("what a cheaper model needs here: " + ("all met" if not unmet else f"{unmet} not met"))
        lines += [condition_line(c) for c in conds]
    why = reason_words(d["auto_reason"], conds)
    shown = head + "  \n" + "  \n".join(lines) + (f"  \n_{why}_" if why else "")
    details = [f"auto's reason: {d['auto_reason']}"]
    if d.get("error_bound_method"):
        details.append(f"how the error estimates were obtained: {d['error_bound_method']}")
    if conds:
        details += ["what a cheaper model needs (the badge's list, as formulas):"]
        details += [f"{'✓' if c.holds else '✗'} {c}" for c in conds]
    return shown, "  \n".join(details)


def fidelity_words(fidelity: str, by_auto: bool) -> str:
    """``full (every moving part integrated, chosen by auto)``: the readout starts with the fidelity's name."""
    words = FIDELITY_WORDS.get(fidelity, fidelity)
    return f"{fidelity} ({words}{', chosen by auto' if by_auto else ''})"


def braking_words(t: float, remaining: float) -> dict[str, str]:
    """The braking readouts on one clock: ``T`` is the time the spin stops, counted like ``t`` from the start
    of the run, and ``remaining`` = T - t; both from the present |K|, so an edit moves both together."""
    if math.isinf(remaining):
        return {"T": "no braking", "remaining": "n/a"}
    return {"T": f"{t + remaining:.6g} s" + (" (stopped)" if remaining <= 0 else ""),
            "remaining": f"{remaining:.6g} s"}


def status_words(message: str) -> str:
    """The run's status message in the panel's words: physics says the braking brought |G| (J* w) to zero,
    a name the panel has nowhere else; to a class, the spin stopped. Where physics names a scenario key the
    panel has a control for (a system's choice action: set KEY = "OPTION"), the control is named; a time given
    to all 17 digits (an IntegrationFault's, exact for a script) is shown to 6."""
    said = message.replace("braking brought |G| to zero", "braking stopped the spin")
    for s in physics.SYSTEMS.values():
        for a in s.actions:
            if a.kind == "choice":
                for option in a.options:
                    said = said.replace(f'set {a.key} = "{option}"', f'choose {a.label} "{option}" (folder {a.folder})')
    return re.sub(r"at t = ([-+]?\d+\.\d{7,}(?:e[-+]?\d+)?)(?! s)", lambda m: f"at t = {float(m.group(1)):.6g} s", said)


def euler_angles(wxyz) -> tuple[float, float, float]:
    """(precession psi, nutation theta, spin phi), rad, z-x-z Euler angles of the body's attitude ``wxyz``
    (body to the view's frame, K up at the start): psi turns about the vertical, theta tilts e3 from it,
    phi turns the body about e3. psi and phi in (-pi, pi]; at theta = 0 psi + phi is what is defined
    (phi is then 0)."""
    w, x, y, z = (float(v) for v in wxyz)
    # the third column (e3 in the view) and third row (the vertical in the body) of the rotation matrix
    r13, r23, r33 = 2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)
    r31, r32 = 2 * (x * z - w * y), 2 * (y * z + w * x)
    theta = math.acos(min(1.0, max(-1.0, r33)))
    if math.hypot(r13, r23) < 1e-12:  # e3 vertical: only psi + phi is defined
        r11, r21 = 1 - 2 * (y * y + z * z), 2 * (x * y + w * z)
        return math.atan2(r21, r11), theta, 0.0
    return math.atan2(r13, -r23), theta, math.atan2(r31, r32)


START_SAME = 5e-5  # rad, and relative for |K|: below this the start is as set (the readouts show 4-6 digits)


def start_words(sc, theta_start: float, K_start: float) -> str:
    """Under the Initial state sliders: the theta(0) and |K(0)| the run starts from, and why they differ from the
    sliders when they do (the sliders set the frozen body's spin J* w0; a moving part's own start adds to K and
    turns it away from that). "" when the run starts as the sliders say."""
    start = {p.label: (p, physics.base_values(sc)[p.key]) for p in physics.BASE_PARAMS if p.restarts}
    angle = next((p, v) for p, v in start.values() if p.unit == "rad")
    size = next((p, v) for p, v in start.values() if p.unit != "rad")
    if abs(theta_start - angle[1]) <= START_SAME and abs(K_start - size[1]) <= START_SAME * max(size[1], 1e-300):
        return ""
    return (f"The run starts at theta(0) = {theta_start:.4g} rad and abs(K(0)) = {K_start:.4g} {size[0].unit}: "
            f"{angle[0].label} = {angle[1]:.4g} and {size[0].label} = {size[1]:.4g} set the frozen body's spin "
            "(J* w0); the moving part's own start adds to K and turns it.")

"""The control panel: which parameters have sliders, their units and the papers' meaning, and how
slider values become a scenario. ``build_panel`` makes the viser widgets; the rest is plain Python.

Every change goes through physics (Scenario.from_dict), so a bad combination raises the same
ScenarioError, naming the key and the allowed range, that a scenario file would.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import physics
from physics import initial_G


@dataclass(frozen=True)
class Param:
    """One slider: ``key`` is the scenario's dotted TOML key; ``label`` what the panel shows."""

    key: str
    label: str
    unit: str
    hint: str
    lo: float
    hi: float
    step: float
    systems: tuple[str, ...] = ("moving_mass",)

    @property
    def text(self) -> str:
        return f"{self.label} ({self.unit})" if self.unit else self.label


MM, SP, PL = "moving_mass", "spherical_pendulum", "plane_pendulums"
ALL = (MM, SP, PL)
PENDULA = (SP, PL)

PARAMS: tuple[Param, ...] = (
    # the six of the braking paper (MODELS.md A.1): the moving mass, the medium and the brake
    Param("mass.m", "m", "kg", "mass of the small body moving inside on a spring-damper; 0 = none; must stay below "
          "the total mass M", 0.0, 1.0, 0.001),
    Param("mass.rho", "rho", "m", "distance from the centre of mass to the moving mass's rest point, on the "
          "symmetry axis", 0.0, 3.0, 0.01),
    Param("mass.Omega", "Omega", "rad/s", "natural frequency of the mass on its spring (Omega^2 = stiffness / m): "
          "a stiffer spring, a higher Omega", 0.5, 60.0, 0.1),
    Param("mass.chi", "chi", "1/s", "damping of the mass's spring: damper force per unit mass and speed "
          "(chi = delta/m); it turns the wobble into heat", 0.0, 60.0, 0.1),
    Param("medium.lambda", "lambda", "1/s", "resistance of the surrounding medium: a torque -lambda J* w against "
          "the rotation; 0 = no medium", 0.0, 0.01, 1e-5),
    Param("control.b", "b", "N m", "strength of the braking torque, always against K; 0 = no braking; the readout T "
          "shows when it stops the spin", 0.0, 0.02, 1e-5),
    # the body
    Param("body.A", "A", "kg m^2", "equatorial principal moment of the frozen system (carrier + parts at rest)", 0.1,
          5.0, 0.01, ALL),
    Param("body.B", "B", "kg m^2", "second equatorial moment; B = A is a symmetric body", 0.1, 5.0, 0.01, ALL),
    Param("body.C", "C", "kg m^2", "axial moment; C > A oblate (settles to spin), C < A prolate (flat spin)", 0.1,
          5.0, 0.01, ALL),
    Param("body.M", "M", "kg", "total mass of the system", 0.1, 20.0, 0.1, ALL),
    Param("mass.lam_q", "lam_q", "1/m", "drag-like friction of the mass, growing with the square of its speed: "
          "force -m lam_q |u'| u'", 0.0, 20000.0, 10.0),
    # the cavity
    Param("cavity.beta", "beta", "kg/m^3", "density of the fluid in the spherical cavity; 0 = no cavity", 0.0,
          2000.0, 1.0),
    Param("cavity.nu", "nu", "m^2/s", "kinematic viscosity of the fluid (Stokes flow needs Re = a0^2 w/nu small)",
          0.1, 100.0, 0.1),
    Param("cavity.a0", "a0", "m", "radius of the spherical cavity", 0.01, 0.5, 0.005),
    # the pendulum dampers
    Param("pendulum.m", "bob m", "kg", "mass of each pendulum bob", 0.001, 0.3, 0.001, PENDULA),
    Param("pendulum.l", "arm l", "m", "pendulum arm length from pivot to bob", 0.01, 1.0, 0.005, PENDULA),
    Param("pendulum.h", "pivot h", "m", "height of the spherical pendulum's pivot above O on the spin axis", -1.0,
          1.0, 0.01, (SP,)),
    Param("pendulum.k", "spring k", "N m/rad", "torsional spring at the pivot; 'tune to resonance' matches the "
          "free nutation", 0.0, 2.0, 0.001, PENDULA),
    Param("pendulum.c_d", "damper c_d", "N m s/rad", "pivot damper", 0.0, 0.2, 0.0005, PENDULA),
    # the initial state
    Param("initial.G0", "G0", "kg m^2/s", "initial angular momentum of the body frozen with its parts at rest, "
          "|J* w0| (the readout |K| adds what the moving parts carry); it defines the start, so changing it "
          "restarts the run from t = 0", 0.1, 10.0, 0.01, ALL),
    Param("initial.theta0", "theta0", "rad", "initial nutation angle between K and e3; it defines the start, "
          "so changing it restarts from t = 0", 0.0, 3.14, 0.01, ALL),
)
BY_KEY = {p.key: p for p in PARAMS}
SIX = ("mass.m", "mass.rho", "mass.Omega", "mass.chi", "medium.lambda", "control.b")
RESTARTING = ("initial.",)  # keys whose change only means something from t = 0

# Defaults used when a slider switches on a part the scenario did not have.
CAVITY_DEFAULTS = {"beta": 1000.0, "nu": 20.0, "a0": 0.1}
MASS_DEFAULTS = {"m": 0.1, "rho": 1.5, "Omega": 8.0, "chi": 8.0}


def values_of(sc: physics.Scenario, bob: int | None = None) -> dict[str, float]:
    """Slider values that describe ``sc`` (0 for an absent part, the part's default otherwise). The
    pendulum sliders show plane pendulum number ``bob`` (0-based), or the first when None."""
    v: dict[str, float] = {"body.A": sc.body.A, "body.B": sc.body.B, "body.C": sc.body.C, "body.M": sc.body.M}
    ms = sc.mass
    v.update({"mass.m": ms.m if ms else 0.0, "mass.rho": ms.rho if ms else MASS_DEFAULTS["rho"],
              "mass.Omega": ms.Omega if ms else MASS_DEFAULTS["Omega"], "mass.chi": ms.chi if ms else 0.0,
              "mass.lam_q": ms.lam_q if ms else 0.0})
    cav = sc.cavity
    v.update({"cavity.beta": cav.beta if cav else 0.0, "cavity.nu": cav.nu if cav else CAVITY_DEFAULTS["nu"],
              "cavity.a0": cav.a0 if cav else CAVITY_DEFAULTS["a0"]})
    v["medium.lambda"] = sc.medium.lambda_ if sc.medium else 0.0
    v["control.b"] = sc.control.b if sc.control else 0.0
    pick = bob if bob is not None and 0 <= bob < len(sc.plane_pendulums) else 0
    bob = sc.pendulum or (sc.plane_pendulums[pick] if sc.plane_pendulums else None)
    v.update({"pendulum.m": bob.m if bob else 0.05, "pendulum.l": bob.l if bob else 0.3,
              "pendulum.h": sc.pendulum.h if sc.pendulum else 0.5,
              "pendulum.k": _stiffness(sc, bob),
              "pendulum.c_d": bob.c_d if bob else 0.01})
    _, G0, theta0 = initial_G(sc)
    v.update({"initial.G0": G0, "initial.theta0": theta0})
    return {k: float(x) for k, x in v.items()}


def _stiffness(sc: physics.Scenario, bob) -> float:
    """A bob's spring k; a tuned one ("resonant", "optimal") as physics resolves it."""
    if bob is None:
        return 0.0
    if isinstance(bob.k, str):  # resolved cheaply: this runs on the tab's loop thread after every change
        ks = physics.resolved_stiffness(sc)
        i = 0 if sc.pendulum is not None else sc.plane_pendulums.index(bob)
        return ks[i]
    return bob.k


def apply_changes(base: physics.Scenario, changes: dict[str, float | str]) -> physics.Scenario:
    """``base`` with the slider changes applied, validated by physics (raises ScenarioError).

    A zero ``lambda``, ``b``, ``beta`` or mass ``m`` removes the medium, the control, the cavity or the
    mass; a positive one adds it. Pendulum values apply to every bob, or with a key ``pendulum.k#i``
    to plane pendulum i (0-based) only. ``pendulum.k`` may be "resonant". ``initial.G0``/``theta0``
    replace an ``omega`` given in the file.
    """
    data = base.to_dict()
    system = base.system
    for full_key, value in changes.items():
        key, _, which = full_key.partition("#")
        table, _, name = key.partition(".")
        if key not in BY_KEY or (which and table != "pendulum"):
            raise physics.ScenarioError(full_key, value, "is not a parameter of the explorer")
        if system not in BY_KEY[key].systems:
            continue  # e.g. a mass slider while a pendulum scene runs: kept for later, not applied
        if table == "body":
            data["body"][name] = value
        elif table == "mass":
            if name == "m" and value == 0:
                data.pop("mass", None)
                continue
            section = data.setdefault("mass", dict(MASS_DEFAULTS))
            section[name] = value
        elif table == "medium":
            if value == 0:
                data.pop("medium", None)
            else:
                data["medium"] = {"lambda": value}
        elif table == "control":
            if value == 0:
                data.pop("control", None)
            else:
                data.setdefault("control", {"law": "K"})["b"] = value
        elif table == "cavity":
            if name == "beta" and value == 0:
                data.pop("cavity", None)
                continue
            if "cavity" not in data and name != "beta":
                continue  # nu, a0 of an absent cavity wait until beta switches it on
            data.setdefault("cavity", dict(CAVITY_DEFAULTS))[name] = value
        elif table == "pendulum":
            if system == "spherical_pendulum":
                data["pendulum"][name] = value
            else:
                bobs = data["plane_pendulum"]
                if which:
                    if not which.isdigit() or int(which) >= len(bobs):
                        raise physics.ScenarioError(full_key, value, f"names no bob: this scene has {len(bobs)}, "
                                                    f"numbered 0 to {len(bobs) - 1}")
                    bobs = [bobs[int(which)]]
                for pp in bobs:
                    pp[name] = value
        elif table == "initial":
            ini = data["initial"]
            if "omega" in ini:
                _, G0, theta0 = initial_G(base)
                ini.pop("omega")
                ini["G0"], ini["theta0"] = G0, theta0
            ini[name] = value
    if "mass" in data:  # switching the mass on: complete it from the current slider defaults
        for k, x in MASS_DEFAULTS.items():
            data["mass"].setdefault(k, x)
    return physics.Scenario.from_dict(data)


def merge_changes(changes: dict, pending: dict) -> dict:
    """``changes`` updated by ``pending``, latest last: a change to every bob (``pendulum.k``) drops the
    earlier per-bob ones (``pendulum.k#i``), so the order of application is the order of the user's moves."""
    out = {k: v for k, v in changes.items() if k not in pending and k.partition("#")[0] not in pending}
    out.update(pending)
    return out


def restarts(changed: dict) -> bool:
    """Whether a change only makes sense from t = 0 (initial conditions)."""
    return any(k.startswith(RESTARTING) for k in changed)


def slider_range(p: Param, value: float) -> tuple[float, float]:
    """The slider's range: the spec's, widened to hold a preset's value with room to move."""
    lo, hi = p.lo, p.hi
    if value > hi:
        hi = float(f"{2 * value:.2g}")
    if value < lo:
        lo = value
    return lo, hi


def fmt(x: float, digits: int = 4) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    if isinstance(x, float) and math.isinf(x):
        return "inf"
    return f"{x:.{digits}g}"


# ---- viser widgets ------------------------------------------------------------------------------

SYSTEM_LABELS = {"moving mass": MM, "spherical pendulum": SP, "plane pendulums": PL}
FIDELITIES = ("auto", "full", "averaged", "closed")
MASS_FOLDER, FRICTION_FOLDER = "Moving mass, medium, braking", "Friction and cavity"  # moving-mass scenes only
FOLDERS = ((MASS_FOLDER, SIX), ("Body inertia", ("body.A", "body.B", "body.C", "body.M")),
           (FRICTION_FOLDER, ("mass.lam_q", "cavity.beta", "cavity.nu", "cavity.a0")),
           ("Pendulum damper", ("pendulum.m", "pendulum.l", "pendulum.h", "pendulum.k", "pendulum.c_d")),
           ("Initial state", ("initial.G0", "initial.theta0")))


def build_sliders(gui, values: dict[str, float]) -> tuple[dict, dict]:
    """Folders of sliders; returns (key -> slider handle, folder title -> folder handle)."""
    sliders, folders = {}, {}
    for title, keys in FOLDERS:
        with gui.add_folder(title, expand_by_default=title == MASS_FOLDER) as folder:
            folders[title] = folder
            for key in keys:
                p = BY_KEY[key]
                lo, hi = slider_range(p, values[key])
                sliders[key] = gui.add_slider(p.text, min=lo, max=hi, step=p.step,
                                              initial_value=min(max(values[key], lo), hi), hint=p.hint)
    return sliders, folders

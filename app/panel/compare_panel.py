"""The Compare folder of one tab's panel: the difference the second run has (another value of one of the
scene's sliders, or another fidelity) and where its body is drawn. Callbacks only queue the engine's
"compare" action (app.engine.compare); ``sync`` shows what the engine runs (off again when a new scene could not
take the difference).
"""

from __future__ import annotations

from ..engine import controls
from ..engine.compare import PLACES, Comparison

OFF, PARAMETER, FIDELITY = "off", "another value of a parameter", "another fidelity"


def suggested(p: controls.Slider, value: float) -> float:
    """The other value offered first: the slider's low end ("without the mass": m = 0), or its high end when
    the scene is already there."""
    return p.lo if value != p.lo else p.hi


def other_fidelity(fidelity: str) -> str:
    return "averaged" if fidelity != "averaged" else "full"


class ComparePanel:
    """Widgets in a "Compare" folder; the second body's place is read by app.scene.compare_view."""

    def __init__(self, gui, engine):
        self.engine = engine
        with gui.add_folder("Compare", expand_by_default=False):
            self.mode = gui.add_dropdown("compare with", [OFF, PARAMETER, FIDELITY], initial_value=OFF,
                                         hint="a second body runs the same scene with one difference, on the same "
                                              "clock, from t = 0; the plots overlay both runs")
            self.param = gui.add_dropdown("parameter", self._labels(), initial_value=self._labels()[0],
                                          hint="the slider whose value the second run changes; the sliders then "
                                               "edit both runs, the difference kept", visible=False)
            self.value = gui.add_number("its other value", 0.0, step=1e-3, visible=False,
                                        hint="the second run's value of that parameter")
            self.fidelity = gui.add_dropdown("other fidelity", list(controls.FIDELITIES), initial_value="averaged",
                                             visible=False, hint="the second run's model")
            self.place = gui.add_dropdown("second body", list(PLACES), initial_value=PLACES[0],
                                          hint="beside the first body, or superimposed on it (both translucent)")
        self._seq = 0  # the last compare request: sync waits until the engine has applied it
        self._busy = False
        self._bind()

    def _request(self, spec) -> None:
        self._seq = self.engine.request("compare", spec)

    def _labels(self) -> list[str]:
        system = self.engine.scenario.system
        return [p.text for p in controls.PARAMS if system in p.systems]

    def _key(self) -> str | None:
        """The slider key the "parameter" dropdown names; None for a label the scene's system does not offer
        (the options changed with the system, or a client sent another)."""
        return next((p.key for p in controls.PARAMS if p.text == self.param.value and p.text in self._labels()),
                    None)

    def _unknown_param(self) -> None:
        self.engine.error = (f"parameter: {str(self.param.value)[:40]!r} refused; expected one of "
                             + ", ".join(self._labels()))

    def _bind(self) -> None:
        def user(handle, fn):
            # async, so viser runs it on its event loop as it stores the value: on a pool thread it could run after
            # sync had set "compare with" back to "off" (no comparison yet) and read that (as app.panel.panel's on())
            @handle.on_update
            async def _(event):
                if event.client is not None:  # our own assignment of a value: not a user's change
                    self._busy = True  # sync leaves the widgets alone until the request is queued
                    try:
                        fn()
                    finally:
                        self._busy = False

        def on_mode():
            mode = self.mode.value
            self.param.visible = self.value.visible = mode == PARAMETER
            self.fidelity.visible = mode == FIDELITY
            if mode == PARAMETER:
                on_param()
            elif mode == FIDELITY:
                self.fidelity.value = other_fidelity(self.engine.scenario.run.fidelity)
                on_fidelity()
            else:
                self._request(None)

        def on_param():
            key = self._key()
            if key is None:
                self._unknown_param()
                return
            self.value.value = suggested(controls.BY_KEY[key], self.engine.values[key])
            self._request((key, float(self.value.value)))

        def on_value():
            try:
                value = float(self.value.value)
            except (TypeError, ValueError):
                self.engine.error = f"its other value: {str(self.value.value)[:40]!r} is not a number"
                return
            key = self._key()
            if key is None:
                self._unknown_param()
                return
            self._request((key, value))

        def on_fidelity():
            self._request(("fidelity", self.fidelity.value))

        def on_place():
            if self.place.value in PLACES:
                self.engine.compare_place = self.place.value  # a display choice: read by app.scene.compare_view

        user(self.mode, on_mode)
        user(self.param, on_param)
        user(self.value, on_value)
        user(self.fidelity, on_fidelity)
        user(self.place, on_place)

    def sync(self) -> None:
        """After a scene change: the parameters the scene has; "off" when the engine turned compare off."""
        labels = self._labels()
        if tuple(self.param.options) != tuple(labels):
            self.param.options = labels
        applied = not self._busy and self.engine.applied_seq >= self._seq
        if applied and not isinstance(self.engine.compare, Comparison) and self.mode.value != OFF:
            self.mode.value = OFF
            self.param.visible = self.value.visible = self.fidelity.visible = False

"""A class's frame computes what every following tab shows once, whatever the number of tabs: the views of one
frame share the end state (which asks the run for its momentum) and the energy plot's pure-spin columns."""

from __future__ import annotations

from collections import Counter

from app.engine.engine import Engine
from app.panel.energy_plot import EnergyChart
from app.serve.class_view import EngineView, Shared

FRAME_S = 1.0 / 60.0


class FakeHandle:
    def __init__(self, **props):
        self.__dict__.update(props)


class FakeGui:
    def add_uplot(self, **kwargs):
        return FakeHandle(**kwargs)


def _one_frame_costs(monkeypatch, tabs: int) -> tuple[Counter, list]:
    """What the views' part of one frame asks of the run, with ``tabs`` following views; and what each drew."""
    eng = Engine()
    for _ in range(3):
        eng.tick(FRAME_S)
    eng.end_state(block=True)  # worked out: each view then reads the cached answer, given K
    shared = Shared(eng)
    views = [EngineView(eng, shared) for _ in range(tabs)]
    charts = [EnergyChart(FakeGui(), eng.plot_data(), (1.0, 1.0, 1.5)) for _ in views]
    counted = Counter()
    run_type, momentum, columns = type(eng.run), type(eng.run).momentum, EnergyChart._columns

    def counted_momentum(self):
        counted["momentum"] += 1
        return momentum(self)

    def counted_columns(data, moments):
        counted["columns"] += 1
        return columns(data, moments)

    monkeypatch.setattr(run_type, "momentum", counted_momentum)
    monkeypatch.setattr(EnergyChart, "_columns", staticmethod(counted_columns))
    eng.tick(FRAME_S)
    shared.take_flags()
    counted.clear()
    for view, chart in zip(views, charts, strict=True):
        view.raise_flags()
        chart.update(view, changed=True)
        view.readouts(), view.details()
    monkeypatch.undo()
    return counted, [c.handle.data for c in charts]


def test_thirty_views_of_one_frame_ask_the_run_as_often_as_one(monkeypatch):
    one, _ = _one_frame_costs(monkeypatch, 1)
    thirty, drawn = _one_frame_costs(monkeypatch, 30)
    assert one["columns"] == 1 and one["momentum"] > 0
    assert thirty == one, (thirty, one)  # once a frame, not once a tab (it was 30 times one)
    assert all(d[0][-1] == drawn[0][0][-1] and len(d) == len(drawn[0]) for d in drawn)  # every tab drew the same

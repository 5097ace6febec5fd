"""Class mode's "Explore from here" (app/engine/branch.py): a new engine at another's scene, state, t and history,
which then runs on its own."""

from __future__ import annotations

import numpy as np

from app.engine.branch import branch
from app.engine.engine import Engine

FRAME_S = 1.0 / 60.0


def test_branch_starts_at_the_source_state_and_is_independent():
    src = Engine()
    for _ in range(20):
        src.tick(FRAME_S)
    src.request_value("mass.m", 0.25)
    for _ in range(5):
        src.tick(FRAME_S)
    b = branch(src)
    assert b.run.t == src.run.t > 0
    assert np.array_equal(b.run.last.table(), src.run.last.table())  # the same state, bit for bit
    assert b.scenario.to_toml() == src.scenario.to_toml() and b.values == src.values and b.preset == src.preset
    for x, y in zip(b.plot_data(), src.plot_data(), strict=True):  # the plots from t = 0
        assert np.array_equal(x, y)
    assert b.plot_data()[0][0] == 0.0
    t_src, m_src = src.run.t, src.scenario.mass.m
    b.request_value("mass.m", 0.3)
    for _ in range(5):
        b.tick(FRAME_S)
    assert b.scenario.mass.m == 0.3 and b.run.t > t_src
    assert src.run.t == t_src and src.scenario.mass.m == m_src  # the source neither stepped nor changed



"""Nothing non-finite is sent to a tab (issue 24, point 2): the braking torque's arrow is finite for any b > 0,
including one whose product with K underflows, and a frame with a NaN or infinity anywhere is not published: the
tab keeps the last finite drawing and is told which part was not finite."""

from __future__ import annotations

import contextlib
import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from app.engine.engine import Engine
from app.engine.frame import non_finite
from app.serve.session import Session

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
DT = 1.0 / 60.0
LENGTH_TOL = 1e-12  # relative: the arrows' drawn lengths are fixed fractions of the body's size
TORQUE_OVER_AXIS = 0.6 / 0.9  # the torque arrow's length over the e3 arrow's (app.engine.frame.make_frame)


@pytest.mark.parametrize("b", [1e-300, 5e-324, 0.01])
def test_the_torque_arrow_is_finite_and_against_K_for_any_braking(b):
    e = Engine()
    e.request_value("control.b", b)
    for _ in range(3):
        fr = e.tick(DT)
    assert e.run.b == b
    assert non_finite(fr) is None
    assert fr.torque_vec is not None
    ratio = np.linalg.norm(fr.torque_vec) / np.linalg.norm(fr.axis_vec)
    assert abs(ratio - TORQUE_OVER_AXIS) < LENGTH_TOL
    cos = fr.torque_vec @ fr.K_vec / (np.linalg.norm(fr.torque_vec) * np.linalg.norm(fr.K_vec))
    assert abs(cos + 1.0) < LENGTH_TOL  # against K


def test_non_finite_names_the_part_that_is_not_finite():
    fr = Engine().tick(DT)
    assert non_finite(fr) is None
    assert non_finite(dataclasses.replace(fr, K_vec=np.array([np.nan, 0.0, 0.0]))) == "K_vec"
    assert non_finite(dataclasses.replace(fr, theta=np.inf)) == "theta"
    if fr.figure:
        p = fr.figure[0]
        field = next(f.name for f in dataclasses.fields(p) if isinstance(getattr(p, f.name), tuple))
        broken = dataclasses.replace(p, **{field: (np.nan,) * len(getattr(p, field))})
        assert non_finite(dataclasses.replace(fr, figure=(broken, *fr.figure[1:]))) == f"{p.name}.{field}"


def test_a_non_finite_frame_is_not_published_the_last_finite_one_is_shown_again():
    engine = Engine()
    drawn: list = []
    s = Session.__new__(Session)  # the publishing alone: no server, no loop thread
    s.engine, s.last_good = engine, None
    s.client = SimpleNamespace(atomic=contextlib.nullcontext)
    s.drawing = SimpleNamespace(update=lambda fr, plots_now: drawn.append((fr, plots_now)))
    s.panel = SimpleNamespace(update=lambda fr, plots_now: None)
    bad = dataclasses.replace(engine.tick(DT), omega_vec=np.array([0.0, np.inf, 0.0]))
    s._publish(bad, True)
    assert drawn == []  # nothing finite to show yet: nothing sent
    good = engine.tick(DT)
    s._publish(good, True)
    s._publish(dataclasses.replace(bad, t=good.t + DT), True)
    assert [fr for fr, _ in drawn] == [good, good]
    assert drawn[-1][1] is False  # the plots are not sent again with it
    assert "omega_vec" in engine.error and "non-finite" in engine.error

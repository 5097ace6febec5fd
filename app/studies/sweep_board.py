"""A sweep's points as clickable cells in the 3-D scene (opt-in from the sweep panel).

viser 1.1.1's plotly chart reports no clicks, so this board is the way to load a point by clicking it.
It lies on the floor in front of the body as the default camera sees it (not behind the control panel);
colour and height follow the heat map's values and outlier-proof scale (sweep_view.coloured, colour_scale).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import physics

from .sweep_view import colour_scale, coloured

BOARD_MAX = 400  # cells drawn in the scene; a larger sweep is listed in the dropdown only
BOARD_SIZE = 2.0  # scene units the board spans (the body spans 1.5)
BOARD_AT = (-0.6, -2.4, -1.38)  # its corner: on the floor grid between the body and the default camera
RAMP = ((68, 1, 84), (33, 145, 140), (253, 231, 37))  # viridis' ends and middle: small values dark
DIVERGING = ((178, 24, 43), (247, 247, 247), (5, 48, 97))  # the heat map's RdBu: grows red, flat white, decays blue
FAILED = (150, 150, 150)


def ramp(x: float) -> tuple[int, int, int]:
    """Colour of a value scaled to [0, 1] (viridis-like, by linear steps between three stops)."""
    x = min(max(x, 0.0), 1.0) * (len(RAMP) - 1)
    i = min(int(x), len(RAMP) - 2)
    f = x - i
    return tuple(int(round(a + f * (b - a))) for a, b in zip(RAMP[i], RAMP[i + 1], strict=True))


def diverging(x: float) -> tuple[int, int, int]:
    """Colour of a value scaled to [-1, 1] around 0 (red below, white at 0, dark blue at the top)."""
    x = min(max(x, -1.0), 1.0)
    a, b = (DIVERGING[1], DIVERGING[2]) if x >= 0 else (DIVERGING[1], DIVERGING[0])
    return tuple(int(round(p + abs(x) * (q - p))) for p, q in zip(a, b, strict=True))


def board_cells(table: physics.SweepTable) -> list[tuple[int, tuple[float, float, float], tuple, float]]:
    """(row, cell centre, colour, height) of every point: the first key along y, the second along x; the
    heat map's values (sweep_view.coloured) through colour_scale (log or clipped) give colour and height:
    dark is small, or for decay_time dark blue is the fastest decay and red is growth; failed points are
    grey and flat."""
    n1 = len(table.axes[0])
    n2 = len(table.axes[1]) if len(table.keys) > 1 else 1
    cell = BOARD_SIZE / max(n1, n2)
    values, what, signed = coloured(table)  # decay_time: its rate 1/tau, as the heat map shows it
    scale = colour_scale(values, what)
    lo, hi = (math.log10(scale.lo), math.log10(scale.hi)) if scale.kind == "log" else (scale.lo, scale.hi)
    top = max(abs(lo), abs(hi)) or 1.0
    out = []
    for i, v in enumerate(values):
        a, b = divmod(i, n2)
        c = scale.apply(float(v))
        if c is None:
            color, height = FAILED, 0.02
        elif signed:  # the fastest decay darkest blue and tallest, growth red
            color, height = diverging(c / top), 0.05 + 0.3 * cell * abs(c) / top
        else:
            x = (c - lo) / (hi - lo) if hi > lo else 0.5
            color, height = ramp(x), 0.05 + 0.3 * cell * x
        centre = (BOARD_AT[0] + (b + 0.5) * cell, BOARD_AT[1] + (a + 0.5) * cell, BOARD_AT[2] + height / 2)
        out.append((i, centre, color, height))
    return out


class SweepBoard:
    """The sweep's points as clickable cells in the scene; ``on_pick(row)`` runs when one is clicked."""

    def __init__(self, scene, on_pick: Callable[[int], None], root: str = "/sweep_board"):
        self.scene, self.on_pick, self.root = scene, on_pick, root
        self.handles: list = []

    def clear(self) -> None:
        for h in reversed(self.handles):
            try:
                h.remove()
            except Exception:  # noqa: BLE001 - already gone with the client
                pass
        self.handles = []

    def show(self, table: physics.SweepTable) -> bool:
        """Draw ``table`` (False, and nothing drawn, beyond BOARD_MAX points)."""
        self.clear()
        if len(table.rows) > BOARD_MAX:
            return False
        cell = BOARD_SIZE / max(len(a) for a in table.axes)
        self.handles.append(self.scene.add_label(
            f"{self.root}/title", f"sweep: {table.metric} (click a cell to load it)",
            position=(BOARD_AT[0], BOARD_AT[1] - 0.15, BOARD_AT[2]), font_screen_scale=0.7))
        for i, centre, color, height in board_cells(table):
            box = self.scene.add_box(f"{self.root}/cell{i}", color=color, dimensions=(0.9 * cell, 0.9 * cell, height),
                                     position=centre, cast_shadow=False, receive_shadow=False)
            box.on_click(lambda _event, i=i: self.on_pick(i))
            self.handles.append(box)
        return True

"""Build assets/meshes/satellite.stl: a box bus, two solar wings on booms, a dish on a mast and four
whip antennas. Run from the repository root: ``python assets/meshes/make_satellite.py``.

Each part is a closed surface and the parts are separated by a millimetre, so the union is watertight
and its volume (hence trimesh's inertia for a uniform solid) is the sum of the parts'. Lengths in
metres, about the size of a small satellite; the explorer rescales the mass to the scenario's M.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh

GAP = 1e-3


def box(extents, centre) -> trimesh.Trimesh:
    return trimesh.creation.box(extents=extents, transform=trimesh.transformations.translation_matrix(centre))


def rod(radius, start, end, sections=16) -> trimesh.Trimesh:
    """A closed cylinder from ``start`` to ``end``."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    return trimesh.creation.cylinder(radius=radius, segment=np.array([start, end]), sections=sections)


def satellite() -> trimesh.Trimesh:
    bus = (1.0, 1.0, 1.4)
    parts = [box(bus, (0, 0, 0))]
    for side in (-1, 1):  # booms and wings along x
        x0 = side * (bus[0] / 2 + GAP)
        x1 = side * (bus[0] / 2 + 0.3)
        parts.append(rod(0.03, (x0, 0, 0), (x1, 0, 0)))
        parts.append(box((2.4, 0.9, 0.03), (x1 + side * (GAP + 1.2), 0, 0)))
    z_top = bus[2] / 2
    parts.append(rod(0.04, (0, 0, z_top + GAP), (0, 0, z_top + 0.35)))  # mast
    dish = trimesh.creation.cone(radius=0.45, height=0.18, sections=32)
    dish.apply_transform(trimesh.transformations.rotation_matrix(np.pi, (1, 0, 0)))  # apex down, onto the mast
    dish.apply_translation((0, 0, z_top + 0.35 + GAP + 0.18))
    parts.append(dish)
    for sx in (-1, 1):  # whips from the bottom corners
        for sy in (-1, 1):
            c = np.array([sx * 0.4, sy * 0.4, -z_top - GAP])
            parts.append(rod(0.01, c, c + (0.25 * sx, 0.25 * sy, -0.9), sections=8))
    mesh = trimesh.util.concatenate(parts)
    assert mesh.is_watertight and mesh.volume > 0
    return mesh


if __name__ == "__main__":
    out = Path(__file__).with_name("satellite.stl")
    m = satellite()
    m.export(out)
    print(f"{out}: {len(m.faces)} faces, volume {m.volume:.4f} m^3, watertight {m.is_watertight}")

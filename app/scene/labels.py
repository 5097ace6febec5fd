"""Labels of the scene's arrows that never print over one another: arrows whose tips are close (nearly
parallel vectors of about the same drawn length, as K, omega and e3 are once a body has settled) share one
label, "K, omega, e3", instead of three stacked ones ("e3omega"). No viser here.
"""

from __future__ import annotations

import numpy as np

LABEL_GAP = 0.15  # labels whose anchors are closer than this fraction of the body's drawn size merge
LABEL_OUT = 1.08  # a label sits this far along its arrow (a little beyond the tip)


def label_groups(vectors: dict[str, np.ndarray | None], size: float, gap: float = LABEL_GAP
                 ) -> list[tuple[str, np.ndarray]]:
    """(text, anchor) per label to draw for the named arrows ``vectors`` (scene units; None or zero = not
    drawn). Arrows whose label anchors lie within ``gap * size`` of each other, directly or through a chain,
    share one label naming them in the given order, anchored at the longest one's. Groups come in the order of
    their first name."""
    names = [n for n, v in vectors.items() if v is not None and float(np.linalg.norm(v)) > 0]
    anchors = {n: LABEL_OUT * np.asarray(vectors[n], dtype=float) for n in names}
    group = {n: i for i, n in enumerate(names)}  # single linkage by union of indices
    limit = gap * size
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if np.linalg.norm(anchors[a] - anchors[b]) < limit:
                old, new = group[b], group[a]
                for n in names:
                    if group[n] == old:
                        group[n] = new
    out = []
    for g in dict.fromkeys(group[n] for n in names):
        members = [n for n in names if group[n] == g]
        longest = max(members, key=lambda n: float(np.linalg.norm(anchors[n])))
        out.append((", ".join(members), anchors[longest]))
    return out

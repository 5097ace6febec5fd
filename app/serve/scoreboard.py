"""The braking challenge in a class (issue 25, point 2): the level and start number the lecturer last raced, which
every student's Braking challenge folder starts from, and the scores the students' attempts reached, which the
lecturer's tab lists. Written from the students' and the lecturer's threads, read by the lecturer's: one lock.

A name is what a student typed, shown in the lecturer's page: kept to MAX_NAME letters, digits, spaces and
``.-'``, so no markdown or HTML of a student's reaches it.
"""

from __future__ import annotations

import math
import re
import threading
from collections import deque
from dataclasses import dataclass

KEPT = 200  # scores remembered (the latest)
LISTED = 15  # the best shown in the lecturer's tab
MAX_NAME = 24
_NOT_NAME = re.compile(r"[^\w .'-]", re.UNICODE)


def clean_name(name) -> str:
    """A student's name as the lecturer's page shows it: "anonymous" when empty."""
    text = _NOT_NAME.sub("", name if isinstance(name, str) else "").replace("_", " ")
    text = " ".join(text.split())[:MAX_NAME]
    return text or "anonymous"


@dataclass(frozen=True)
class Score:
    name: str
    title: str  # the level and start number ("A rigid body · start 3")
    score: float  # T / T_student
    seconds: float  # T_student


class Scoreboard:
    """The class's challenge: the lecturer's choice and the students' scores."""

    def __init__(self):
        self._lock = threading.Lock()
        self._scores: deque[Score] = deque(maxlen=KEPT)
        self._choice: tuple[str, int] | None = None
        self.version = 0  # bumped by every change: the lecturer's tab redraws its list only then

    def choose(self, level: str, seed: int) -> None:
        """The lecturer started a race: the students' folders offer its level and start number."""
        with self._lock:
            self._choice = (level, int(seed))
            self.version += 1

    def choice(self) -> tuple[str, int] | None:
        with self._lock:
            return self._choice

    def post(self, name, title: str, score: float, seconds: float) -> None:
        """A student's attempt ended with ``score``; a non-finite or non-positive one is not a score."""
        if not (isinstance(score, float) and math.isfinite(score) and score > 0 and math.isfinite(seconds)):
            return
        with self._lock:
            self._scores.append(Score(clean_name(name), str(title)[:80], score, seconds))
            self.version += 1

    def scores(self) -> list[Score]:
        with self._lock:
            return sorted(self._scores, key=lambda s: -s.score)

    def markdown(self) -> str:
        """The best LISTED scores, one line each; a line saying none yet."""
        best = self.scores()
        if not best:
            return "**Class scores** · none yet: a student's score appears here when their body stops"
        n = len(best)
        lines = [f"**Class scores** · {n} attempt{'s' if n != 1 else ''}, the best {min(LISTED, n)}:"]
        lines += [f"{i}. {s.name} · {s.title} · score {s.score:.2f} ({s.seconds:.1f} s)"
                  for i, s in enumerate(best[:LISTED], 1)]
        return "  \n".join(lines)

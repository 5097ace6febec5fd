"""The braking challenge in a class (issue 25, point 2), headless: the lecturer's Start gives every student's folder
its level and start number, a student's attempt that stops posts its score once under a cleaned name, and the
lecturer's folder lists the class's scores. Panels on a recording GUI (no viser), engines driven as the loop
would."""

from __future__ import annotations

import numpy as np
from test_app_words import _RecordingGui
from test_challenge import DT, scripted

from app.engine import challenge
from app.engine.engine import Engine
from app.panel.challenge_panel import ChallengePanel, ClassChallenge
from app.serve.scoreboard import Scoreboard, clean_name


def click(handle, value=None):
    for cb in handle.callbacks:
        cb(value)


def folder(board: Scoreboard, role: str) -> tuple[ChallengePanel, Engine]:
    eng = Engine()
    hooks = (ClassChallenge(choice=board.choice, chose=board.choose, board=board.markdown) if role == "lecturer"
             else ClassChallenge(choice=board.choice, post=board.post))
    return ChallengePanel(_RecordingGui(), eng, hooks), eng


def test_the_lecturer_s_start_is_every_student_s_and_a_student_s_score_reaches_the_lecturer_once():
    board = Scoreboard()
    lecturer, class_engine = folder(board, "lecturer")
    assert lecturer.name is None and lecturer.board_md is not None  # the lecturer lists; students post
    lecturer.level.value, lecturer.seed.value = challenge.level_title("with_mass"), 7
    click(lecturer.start)
    class_engine._apply_pending()
    assert board.choice() == ("with_mass", 7) and class_engine.challenge.seed == 7

    student, own = folder(board, "student")  # a student exploring after the lecturer's Start
    assert (student.level.value, student.seed.value) == (challenge.level_title("with_mass"), 7)
    assert student.board_md is None and student.name is not None
    student.name.value = "Ana <b>*|[x](y)"
    click(student.start)
    own._apply_pending()
    np.testing.assert_array_equal(own.run.last.omega, class_engine.run.last.omega)  # one start for the class
    ch = own.challenge
    while not ch.over:
        own.request("thrust", scripted(own))
        own._apply_pending()
        challenge.before_advance(own)
        own._advance(DT)
    student.update()
    student.update()  # once only
    (posted,) = board.scores()
    assert posted.name == "Ana bxy" and posted.score == ch.score and posted.seconds == ch.finished_at
    assert posted.title == "With the moving mass · start 7"
    lecturer.update()
    assert f"Ana bxy · With the moving mass · start 7 · score {ch.score:.2f}" in lecturer.board_md.content


def test_a_refused_start_number_never_becomes_the_class_s():
    board = Scoreboard()
    lecturer, eng = folder(board, "lecturer")
    lecturer.seed.value = float("nan")
    click(lecturer.start)
    eng._apply_pending()
    assert board.choice() is None and eng.challenge is None
    assert "challenge start number nan is not a whole number" in eng.error


def test_names_scores_and_the_list_s_words():
    assert clean_name("") == clean_name(None) == clean_name(3) == "anonymous"
    assert clean_name("  <script>alert(1)</script> ") == "scriptalert1script"
    assert clean_name("Zoë O'Neil-Smith") == "Zoë O'Neil-Smith" and len(clean_name("x" * 500)) == 24
    board = Scoreboard()
    assert "none yet" in board.markdown()
    for bad in (float("nan"), float("inf"), -1.0, 0.0):
        board.post("x", "t", bad, 10.0)
    assert board.scores() == []
    board.post("b", "t", 0.5, 40.0)
    board.post("a", "t", 0.7, 28.0)
    assert [s.name for s in board.scores()] == ["a", "b"]  # best first
    assert board.markdown().startswith("**Class scores** · 2 attempts, the best 2:")

"""A command-line value that begins with a minus sign is a value. argparse (3.11 to 3.13) takes only ``-1`` and
``-.5`` for negative numbers: ``--seconds -1e308``, ``-5e-324`` or ``-inf`` after an option was read as an option
of its own, and the error ("expected one argument") named neither the value nor what is allowed. With this
matcher the value reaches the option's own check, which says both. (physics.cli attaches such values instead;
the app may not import it.)"""

from __future__ import annotations

import argparse
import re

# what argparse then reads as a value, not an option: a minus and a digit, a point and a digit, inf or nan
NEGATIVE = re.compile(r"^-(?:\d|\.\d|inf|nan)", re.IGNORECASE)


def numbers_as_values(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """``parser``, reading ``--opt -1e308`` as the option and its value. argparse keeps the matcher as a plain
    attribute of the parser (since Python 2.7); tests/test_app_record.py fails if a Python stops reading it."""
    parser._negative_number_matcher = NEGATIVE
    return parser

"""The DOP853 tableau (Hairer's coefficients, as scipy ships them), read without importing
``scipy.integrate``.

Importing ``scipy.integrate`` pulls in quadrature, BVP and scipy.special: 0.4 s of the explorer's
start-up (``python -X importtime -m app``) for a module that holds only numpy arrays. The file is
loaded on its own from scipy's installed tree instead; it imports nothing but numpy.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import scipy  # its __init__ is lazy: cheap


def _load():
    path = Path(scipy.__file__).parent / "integrate" / "_ivp" / "dop853_coefficients.py"
    spec = importlib.util.spec_from_file_location("_quasirigid_dop853_coefficients", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


DOP853 = _load()

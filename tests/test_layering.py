"""physics stays headless: importing it pulls in neither viser nor anything from app."""

import subprocess
import sys


def test_physics_imports_no_gui():
    code = (
        "import sys, physics, physics.cli, physics.systems.moving_mass.closed\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('viser', 'app'))\n"
        "print(','.join(bad))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""

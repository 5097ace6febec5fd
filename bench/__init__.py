"""Work-precision and stability studies of the physics core (issue 5). ``python -m bench --help``.

Each command writes CSV (and JSON metadata: machine, versions, command) into bench/results/ and
charts into docs/img/. bench imports physics (and, for the MuJoCo peers, the verified MuJoCo
models in tests/); physics never imports bench.
"""

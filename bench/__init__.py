"""The project's studies and benchmarks, one subcommand each: ``python -m bench --help`` lists them.

Each command writes CSV (and JSON metadata: machine, versions, command) into bench/results/ and
charts into docs/img/. bench imports physics (its benchmark problems, numpy and MuJoCo peers from
physics/reference/, which the tests share); physics never imports bench.
"""

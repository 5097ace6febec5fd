"""Independent references for checking the models: what the tests and the benchmarks compare the product with.

- ``averaged_equations``: the averaged equations of seeds 004 and 000 as plain numpy right-hand sides, written
  out from the papers (docs/models.md A.3, A.6) without the model code, for the closed-form tests and figures;
- ``problems``: the benchmark problems P1-P4 of issue 5 and their exact or reference solutions;
- ``numpy_rhs``: the full models as a scipy user would write them in numpy (the benchmark's scipy peer);
- ``mujoco_common``, ``mujoco_moving_mass``, ``mujoco_pendulum``: the same bodies built in MuJoCo, another engine.

Nothing in the product imports this package (``import physics`` does not load it), and only the ``mujoco_*``
modules import MuJoCo, a test dependency (``pip install -e ".[test]"``), not a base one.
"""

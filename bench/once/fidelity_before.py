"""Issue 15's "before": the code before it (commit f492b95) on the study's scenarios: auto's pick (no run.accuracy)
and its old averaged_error_bound, against the actual errors the study measured.

    git worktree add /tmp/before f492b95
    PYTHONPATH=/tmp/before python bench/once/fidelity_before.py bench/results/fidelity_calibration.csv \
        bench/results/fidelity_before.json

(bench/results/fidelity_calibration.csv holds the seed-15 study's scenarios and measurements; it was
bench/results/fidelity.csv until issue 23 made seed 15 the calibration set.)

Not a bench subcommand (bench/once/ holds one-off comparisons): it must import the old physics, not this tree's.
"""

from __future__ import annotations

import csv
import json
import sys
import warnings


def main(csv_path: str, out_path: str | None = None) -> dict:
    import physics  # the old tree's, through PYTHONPATH

    warnings.simplefilter("ignore")
    scenarios: dict[str, list[dict]] = {}
    with open(csv_path, newline="") as fh:
        for r in csv.DictReader(fh):
            scenarios.setdefault(r["index"], []).append(r)
    cheaper = off2 = off3 = 0
    ratios = []
    for group in scenarios.values():
        d = physics.derived(physics.Scenario.from_dict(json.loads(group[0]["scenario"])))
        actual = {r["fidelity"]: float(r["actual_error"]) for r in group if r["status"] == "ok"}
        fid = d["auto_fidelity"]
        if fid != "full":
            cheaper += 1
            off2 += actual.get(fid, 0.0) > 1e-2
            off3 += actual.get(fid, 0.0) > 1e-3
        if d.get("averaged_error_bound") is not None and "averaged" in actual:
            ratios.append(actual["averaged"] / d["averaged_error_bound"])
    ratios.sort()
    result = dict(physics=physics.__file__, scenarios=len(scenarios), old_auto_cheaper=cheaper,
                  old_auto_cheaper_off_by_more_than_1e_2=off2, old_auto_cheaper_off_by_more_than_1e_3=off3,
                  old_estimates=len(ratios), old_over_1=sum(x > 1 for x in ratios),
                  old_worst_actual_over_estimate=ratios[-1], old_median_actual_over_estimate=ratios[len(ratios) // 2])
    text = json.dumps(result, default=float, indent=2)
    print(text)
    if out_path:
        with open(out_path, "w") as fh:
            fh.write(text + "\n")
    return result


if __name__ == "__main__":
    main(*sys.argv[1:3])

"""``redik regress``: baselines written, compared by the stated rules; a degradation fails."""

from __future__ import annotations

import gc
import io
import json
import sys
import textwrap
from pathlib import Path

import pytest

from redik.apps.cli import main
from redik.apps.regress import compare, load_baseline, run_regression

SPEC = '''
"""A spec whose quality is set by the constants below (edited to inject a degradation)."""
import numpy as np

STEP = 1.0          # Newton step length on x² = 2: 1.0 converges quadratically
MAX_ITERATIONS = 50
CRITERIA = {"success_rate": ">= 0.5"}


def run(ctx):
    targets = ctx.rng.uniform(1.0, 4.0, size=ctx.size(full=40, fast=10))
    iterations, errors, solved = [], [], []
    for target in targets:
        x = 1.0
        for k in range(MAX_ITERATIONS):
            if abs(x * x - target) <= 1e-12:
                break
            x += STEP * (target - x * x) / (2.0 * x)
        iterations.append(k)
        errors.append(abs(x * x - target))
        solved.append(errors[-1] <= 1e-12)
    return {
        "success_rate": float(np.mean(solved)),
        "max_final_error": max(errors),
        "mean_iterations": float(np.mean(iterations)),
    }
'''


def make_specs(folder: Path) -> Path:
    folder.mkdir()
    (folder / "sqrt_newton.py").write_text(textwrap.dedent(SPEC))
    return folder


def degrade(folder: Path, old: str, new: str) -> None:
    path = folder / "sqrt_newton.py"
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))


def test_update_writes_baselines_and_an_unchanged_rerun_passes(tmp_path):
    specs = make_specs(tmp_path / "specs")
    report = run_regression(specs, fast=True, update=True)
    assert not report.regressed
    baseline_file = specs / "baselines" / "sqrt_newton.json"
    assert report.updated == [baseline_file]
    stored = json.loads(baseline_file.read_text())
    assert set(stored["fast"]["metrics"]) == {"success_rate", "max_final_error", "mean_iterations"}
    assert load_baseline(baseline_file, "full") is None
    rerun = run_regression(specs, fast=True)
    assert not rerun.regressed, rerun.table()
    statuses = {c.metric: c.status for c in rerun.specs[0].comparisons}
    assert statuses["mean_iterations"] == "ok" and statuses["success_rate"] == "ok"


@pytest.mark.parametrize(
    ("old", "new", "metric"),
    [
        ("STEP = 1.0 ", "STEP = 0.5 ", "mean_iterations"),  # linear instead of quadratic
        (
            "MAX_ITERATIONS = 50",
            "MAX_ITERATIONS = 4",
            "success_rate",
        ),  # budget too small for some targets
    ],
)
def test_injected_degradation_is_caught(tmp_path, capsys, old, new, metric):
    specs = make_specs(tmp_path / "specs")
    assert main(["regress", "--fast", "--update", "--specs", str(specs)]) == 0
    assert main(["regress", "--fast", "--specs", str(specs)]) == 0
    degrade(specs, old, new)
    assert main(["regress", "--fast", "--specs", str(specs)]) == 1
    printed = capsys.readouterr().out
    regressed_rows = [line for line in printed.splitlines() if "REGRESSED" in line]
    assert any(metric in line for line in regressed_rows), printed


def test_failing_criteria_count_as_regression_and_block_update(tmp_path):
    specs = make_specs(tmp_path / "specs")
    degrade(specs, '">= 0.5"', '">= 2"')
    baselines = tmp_path / "baselines"
    assert (
        main(
            ["regress", "--fast", "--update", "--specs", str(specs), "--baselines", str(baselines)]
        )
        == 1
    )
    assert not (baselines / "sqrt_newton.json").exists()


def test_a_crashing_spec_is_a_regression(tmp_path):
    specs = make_specs(tmp_path / "specs")
    degrade(specs, "x = 1.0\n", "x = 1.0 / 0.0\n")
    report = run_regression(specs, fast=True)
    assert report.regressed
    assert "ZeroDivisionError" in report.table()
    assert gc.get_freeze_count() == 0  # the warm-up's objects are frozen during the specs only


def test_comparison_rules():
    base = {
        "success_rate": 1.0,
        "pos_error": 1e-10,
        "mean_iterations": 4.0,
        "n_solutions": 8,
        "time_ratio": 10.0,
        "note": 3.0,
    }
    same = {c.metric: c.status for c in compare(base, base)}
    assert same == {
        "success_rate": "ok",
        "pos_error": "ok",
        "mean_iterations": "ok",
        "n_solutions": "ok",
        "time_ratio": "ok",
        "note": "info",
    }
    within = {
        **base,
        "success_rate": 0.99,
        "pos_error": 5e-9,
        "mean_iterations": 6.0,
        "time_ratio": 25.0,
        "note": 99.0,
    }
    assert all(c.status != "REGRESSED" for c in compare(within, base))
    worse = {
        "success_rate": 0.97,
        "pos_error": 1e-6,
        "mean_iterations": 7.0,
        "n_solutions": 7,
        "time_ratio": 33.0,
        "note": 0.0,
    }
    statuses = {c.metric: c.status for c in compare(worse, base)}
    assert statuses == {
        "success_rate": "REGRESSED",
        "pos_error": "REGRESSED",
        "mean_iterations": "REGRESSED",
        "n_solutions": "REGRESSED",
        "time_ratio": "REGRESSED",
        "note": "info",
    }
    better = {c.metric: c.status for c in compare({**base, "mean_iterations": 2.0}, base)}
    assert better["mean_iterations"] == "improved"
    missing = {c.metric: c.status for c in compare({"note": 1.0}, base)}
    assert missing["success_rate"] == "REGRESSED"


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_covers_the_warm_up_and_names_each_spec(tmp_path, monkeypatch):
    specs = make_specs(tmp_path / "specs")
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    run_regression(specs, fast=True, show_progress=True)
    drawn = terminal.getvalue()
    # Four steps: the warm-up, the two reference timings and the one spec.
    assert "warm-up" in drawn and "sqrt_newton" in drawn and "4/4" in drawn, drawn


def test_regress_cli_is_quiet_with_quiet(tmp_path, monkeypatch):
    specs = make_specs(tmp_path / "specs")
    terminal = _Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    assert main(["regress", "--fast", "--update", "--specs", str(specs), "--quiet"]) == 0
    assert terminal.getvalue() == ""
    assert main(["regress", "--fast", "--specs", str(specs)]) == 0
    assert "sqrt_newton" in terminal.getvalue()

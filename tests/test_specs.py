"""Specs: loading, criteria, crash handling, the summary table, and every bundled spec."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import pytest

import redik
from redik.apps.regress import default_specs_dir
from redik.apps.specs import (
    Context,
    Spec,
    SuccessCriterion,
    discover,
    load_spec,
    run_spec,
    summary_table,
)

BUNDLED = discover(default_specs_dir()) if default_specs_dir().is_dir() else []


def write_spec(folder: Path, name: str, body: str) -> Path:
    path = folder / f"{name}.py"
    path.write_text(textwrap.dedent(body))
    return path


@pytest.mark.parametrize(
    ("text", "value", "holds"),
    [
        (">= 0.99", 1.0, True),
        (">= 0.99", 0.5, False),
        ("<= 1e-6", 2e-7, True),
        ("== 8", 8, True),
        ("< 3", 3, False),
        ("> -inf", -1e300, True),
        (8, 8.0, True),
    ],
)
def test_criterion_parses_and_checks(text, value, holds):
    assert SuccessCriterion.parse("m", text).holds(value) is holds


def test_criterion_never_holds_for_missing_or_nan():
    criterion = SuccessCriterion.parse("m", "<= 1")
    assert not criterion.holds(None)
    assert not criterion.holds(math.nan)


@pytest.mark.parametrize("text", ["about 3", "=> 1", ">= one", ""])
def test_bad_criterion_is_rejected(text):
    with pytest.raises(redik.InvalidInput, match="criterion"):
        SuccessCriterion.parse("m", text)


def test_spec_file_is_loaded_and_run(tmp_path):
    path = write_spec(
        tmp_path,
        "toy",
        '''
        """A toy spec: counts in the requested mode."""
        CRITERIA = {"count": ">= 3", "max_error": "<= 1e-3"}

        def run(ctx):
            n = ctx.size(full=100, fast=5)
            values = list(ctx.progress(range(n), total=n))
            ctx.path("note.txt").write_text("ran")
            return {"count": len(values), "max_error": 1e-4, "seed": ctx.seed}
        ''',
    )
    spec = load_spec(path)
    assert spec.name == "toy"
    assert spec.description == "A toy spec: counts in the requested mode."
    outcome = run_spec(spec, Context(fast=True, seed=7, out=tmp_path / "out"))
    assert outcome.passed and outcome.error is None
    assert outcome.metrics == {"count": 5.0, "max_error": 1e-4, "seed": 7.0}
    assert (tmp_path / "out" / "note.txt").read_text() == "ran"
    table = summary_table(outcome)
    assert "PASSED" in table and "count" in table and "ok" in table


def test_failed_criterion_and_missing_metric_fail_the_spec():
    spec = Spec("bad", run=lambda ctx: {"a": 2.0}, criteria={"a": "<= 1", "b": ">= 0"})
    outcome = run_spec(spec)
    assert not outcome.passed
    assert [check.passed for check in outcome.checks] == [False, False]
    table = summary_table(outcome)
    assert "FAILED" in table and "missing" in table


def test_a_crashing_spec_is_reported_not_raised():
    def run(ctx):
        raise RuntimeError("boom in the spec")

    outcome = run_spec(Spec("crash", run=run, criteria={}))
    assert not outcome.passed
    assert "boom in the spec" in outcome.error
    assert outcome.metrics == {}


def test_run_must_return_metrics():
    outcome = run_spec(Spec("none", run=lambda ctx: None))
    assert not outcome.passed and "dict of metrics" in outcome.error


def test_spec_without_run_or_file_is_misuse(tmp_path):
    with pytest.raises(redik.InvalidInput, match="run"):
        load_spec(write_spec(tmp_path, "norun", "X = 1\n"))
    with pytest.raises(redik.InvalidInput, match="not found"):
        load_spec(tmp_path / "missing.py")
    with pytest.raises(redik.InvalidInput, match="CRITERIA"):
        load_spec(write_spec(tmp_path, "badcrit", "CRITERIA = 3\ndef run(ctx):\n    return {}\n"))


def test_cli_run_exit_code_follows_the_criteria(tmp_path, capsys):
    from redik.apps.cli import main

    good = write_spec(
        tmp_path, "good", 'CRITERIA = {"x": ">= 1"}\ndef run(ctx):\n    return {"x": 1}\n'
    )
    bad = write_spec(
        tmp_path, "bad", 'CRITERIA = {"x": ">= 2"}\ndef run(ctx):\n    return {"x": 1}\n'
    )
    out = ["--out", str(tmp_path / "out"), "--no-progress", "--fast"]
    assert main(["run", str(good), *out]) == 0
    assert main(["run", str(bad), *out]) == 1
    assert "good (fast" in capsys.readouterr().out


def test_there_are_bundled_specs():
    names = {path.stem for path in BUNDLED}
    assert len(names) >= 6, names


@pytest.mark.parametrize("path", BUNDLED, ids=[path.stem for path in BUNDLED])
def test_every_bundled_spec_passes_in_fast_mode(path, tmp_path):
    outcome = run_spec(path, Context(fast=True, out=tmp_path))
    assert outcome.error is None, outcome.error
    assert outcome.passed, summary_table(outcome)

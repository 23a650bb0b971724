"""redik.core.compile_ahead: the steps of a module, and modules in parallel processes."""

from __future__ import annotations

import subprocess

import pytest

from redik.core import compile_ahead


def test_compile_all_runs_each_step_once_in_order_and_reports_it():
    calls: list[str] = []
    lines: list[str] = []
    seconds = compile_ahead.compile_all(
        {"a": lambda: calls.append("a"), "b": lambda: calls.append("b")}, lines.append
    )
    assert calls == ["a", "b"]
    assert list(seconds) == ["a", "b"] and all(s >= 0.0 for s in seconds.values())
    assert [line.split()[0] for line in lines] == ["a", "b"]


def test_run_modules_runs_each_module_in_its_own_process_and_reports_its_output():
    lines: list[str] = []
    seconds = compile_ahead.run_modules(["this", "__hello__"], jobs=2, report=lines.append)
    assert sorted(seconds) == ["__hello__", "this"]
    assert sorted(line.split(":")[0] for line in lines) == [
        "python -m __hello__",
        "python -m this",
    ]
    assert any("Beautiful is better than ugly." in line for line in lines)
    assert any("Hello world!" in line for line in lines)


def test_run_modules_raises_with_the_output_of_a_module_that_fails():
    with pytest.raises(subprocess.CalledProcessError) as failure:
        compile_ahead.run_modules(["redik.no_such_module"], jobs=1, report=lambda _: None)
    assert "No module named redik.no_such_module" in failure.value.output


def test_every_compile_ahead_module_is_listed_and_the_install_set_is_part_of_it():
    assert set(compile_ahead.INSTALL) <= set(compile_ahead.EVERY)
    for module in compile_ahead.EVERY:
        assert module.endswith(".compile")
        assert __import__(module, fromlist=["STEPS"]).STEPS

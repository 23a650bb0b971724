"""Recorded benchmark results: ``redik bench NAME --record FILE`` and the tables made from them."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from redik.apps import measured
from redik.apps.cli import main
from redik.core.exceptions import InvalidInput

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(autouse=True)
def _fresh_tables():
    measured.start()
    yield
    measured.start()


def test_column_names_carry_the_unit_of_their_keyword():
    assert measured.column_name("redik_us") == "redik µs"
    assert measured.column_name("wall_per_s") == "wall /s"
    assert measured.column_name("success_pct") == "success %"
    assert measured.column_name("p99_ms") == "p99 ms"
    assert measured.column_name("mink_over_redik") == "mink over redik"
    assert measured.column_name("_us") == " us"  # a bare suffix names no unit


def test_a_row_with_other_columns_than_the_first_is_refused():
    measured.record("t", robot="panda", median_us=1.0)
    with pytest.raises(InvalidInput, match="median µs"):
        measured.record("t", robot="panda", mean_us=1.0)


def test_the_command_line_drops_only_the_record_option():
    argv = ["bench", "pose", "--record", "x.json", "--quick", "--record=y.json"]
    assert measured.command_line(argv) == "redik bench pose --quick"
    tool = measured.command_line(["--runs", "3", "--record", "x.json"], "python tools/first_run.py")
    assert tool == "python tools/first_run.py --runs 3"


def test_a_recorded_run_round_trips_with_its_command(tmp_path):
    measured.record("steps", robot="panda", median_us=12.345678, success_pct=99.5, note=None)
    measured.record("steps", robot="ur5e", median_us=float("nan"), success_pct=100, note="x")
    path = measured.write(tmp_path / "sub" / "k.json", "k", ["bench", "k", "--n", "3"], (1, 2, 3))
    (run,) = measured.load([path])
    assert run["benchmark"] == "k"
    assert run["command"] == "redik bench k --n 3"
    assert run["load_average"]["start"] == [1, 2, 3]
    (table,) = run["tables"]
    assert table["columns"] == ["robot", "median µs", "success %", "note"]
    assert table["rows"] == [["panda", 12.345678, 99.5, None], ["ur5e", None, 100, "x"]]


def _table() -> dict:
    return {
        "title": "t",
        "columns": ["solver", "median ms", "ratio"],
        "rows": [["a", 0.5, 2.0], ["a", 0.25, 3.0], ["b", 7.0, 1.0]],
    }


def test_a_headline_is_the_range_of_its_column_over_the_matching_rows():
    headline = measured.Headline("a median", "median ms", {"solver": "a"})
    assert measured.figure(_table(), headline) == "a median 0.250–0.500 ms"
    assert measured.figure(_table(), measured.Headline("b", "ratio", {"solver": "b"})) == "b 1"


def test_a_headline_naming_a_missing_column_or_row_is_refused():
    with pytest.raises(InvalidInput, match="no column 'p99 ms'"):
        measured.figure(_table(), measured.Headline("x", "p99 ms"))
    with pytest.raises(InvalidInput, match="no row"):
        measured.figure(_table(), measured.Headline("x", "ratio", {"solver": "c"}))


@pytest.mark.parametrize(
    ("value", "text"),
    [(None, "—"), ("daqp", "daqp"), (12, "12"), (123456.0, "123,456"), (123.4, "123"),
     (12.34, "12.3"), (1.234, "1.23"), (0.1234, "0.123"), (1.5e-7, "1.5e-07"), (10.0, "10"),
     (0.0, "0"), (62.0, "62"), (10.5, "10.5"), (0.5, "0.500")],
)  # fmt: skip
def test_cells_keep_about_three_significant_digits(value, text):
    assert measured.format_number(value) == text


def test_the_readme_block_is_replaced_between_its_markers_only():
    text = f"head\n{measured.README_START}\nold\n{measured.README_END}\ntail\n"
    replaced = measured.replace_block(text, "NEW")
    assert replaced == "head\nNEW\ntail\n"
    with pytest.raises(InvalidInput, match="markers"):
        measured.replace_block("no markers", "NEW")


def test_readme_measured_table_is_rendered_from_the_recorded_files():
    """No figure in README's Measured table is typed by hand: it is what `make measured` writes."""
    recorded = sorted((ROOT / "docs" / "measured").glob("*.json"))
    assert recorded
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    block = measured.render_readme(recorded)
    assert measured.replace_block(readme, block) == readme, "run `make measured`"
    tools = {"first_run": "python tools/first_run.py"}  # recorded by a script of tools/
    for run in measured.load(recorded):
        program = tools.get(run["benchmark"], f"redik bench {run['benchmark']}")
        assert run["command"].startswith(program)
        assert run["tables"], run["benchmark"]


def test_every_headline_names_a_recorded_table():
    recorded = measured.load(sorted((ROOT / "docs" / "measured").glob("*.json")))
    titles = {table["title"] for run in recorded for table in run["tables"]}
    assert set(measured.HEADLINES) <= titles


@pytest.mark.slow
def test_bench_record_writes_what_the_benchmark_printed(tmp_path, capsys):
    path = tmp_path / "kinematics.json"
    argv = ["bench", "kinematics", "--robots", "ur5e", "--calls", "20", "--repeats", "1"]
    assert main([*argv, "--record", str(path)]) == 0
    printed = capsys.readouterr().out
    run = json.loads(path.read_text(encoding="utf-8"))
    assert run["command"] == "redik " + " ".join(argv)
    (table,) = run["tables"]
    assert table["columns"] == ["robot", "case", "median µs", "vs raw"]
    assert len(table["rows"]) == sum(line.startswith("ur5e") for line in printed.splitlines())
    for robot, case, median, _ in table["rows"]:
        assert robot == "ur5e"
        assert case in printed
        assert f"{median:.2f}" in printed

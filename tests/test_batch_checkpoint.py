"""A batch with a checkpoint resumes after a crash without solving its finished chunks again,
returns what an uninterrupted run returns, and refuses a checkpoint of another batch."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import redik
from redik.core.exceptions import CheckpointMismatch
from redik.solvers.batch import Chain, forward_kinematics, solve_batch
from redik.solvers.batch import checkpoint as checkpoint_module
from redik.solvers.batch import solve as solve_module
from redik.solvers.batch.checkpoint import FINGERPRINT_FILE, finished_chunks

CHUNK = 50


@pytest.fixture(scope="module")
def problem() -> tuple[Chain, np.ndarray]:
    """300 panda targets: reachable ones, an invalid one, and unreachable ones whose results
    depend on the random restarts (so a different key would show)."""
    robot = redik.load("panda")
    chain = Chain.from_robot(robot)
    T = forward_kinematics(chain, robot.random_q(3, size=300))
    T[7, 0, 0] = np.nan
    T[::25, :3, 3] += 3.0  # 3 m further: out of reach, every restart is spent
    return chain, T


class _Crash(Exception):
    """Stands for the process dying after some chunks."""


def _crash_after(chunks: int):
    seen = []

    def progress(size: int) -> None:
        seen.append(size)
        if len(seen) == chunks:
            raise _Crash

    return progress


def _assert_identical(a, b) -> None:
    for field in dataclasses.fields(a):
        np.testing.assert_array_equal(getattr(a, field.name), getattr(b, field.name))


@pytest.fixture
def solved_chunks(monkeypatch) -> list[int]:
    """The first target of every chunk solved from now on (the local engine runs them here)."""
    solved: list[int] = []
    solve_chunk = solve_module.solve_chunk

    def counted(chain, T, q0, options, key, first=0, parallel=False):
        solved.append(first)
        return solve_chunk(chain, T, q0, options, key, first, parallel)

    monkeypatch.setattr(solve_module, "solve_chunk", counted)
    return solved


def test_a_batch_cut_short_resumes_without_solving_its_finished_chunks(
    problem, tmp_path, solved_chunks
):
    chain, T = problem
    options = {"seed": 4, "restarts": 3, "chunk_size": CHUNK, "engine": "local"}
    whole = solve_batch(chain, T, **options)
    solved_chunks.clear()
    with pytest.raises(_Crash):
        solve_batch(chain, T, **options, checkpoint=tmp_path, progress=_crash_after(2))
    assert finished_chunks(tmp_path) == 2  # written as each arrived
    assert solved_chunks == [0, 50]
    solved_chunks.clear()
    reported: list[int] = []
    resumed = solve_batch(chain, T, **options, checkpoint=tmp_path, progress=reported.append)
    assert solved_chunks == [100, 150, 200, 250]  # the two finished chunks were read
    assert reported == [CHUNK] * 6  # progress counts the chunks read too
    _assert_identical(resumed, whole)
    solved_chunks.clear()
    again = solve_batch(chain, T, **options, checkpoint=tmp_path)  # all finished: nothing solved
    assert solved_chunks == []
    _assert_identical(again, whole)


def test_a_checkpoint_resumes_on_another_engine(problem, tmp_path):
    chain, T = problem
    options = {"seed": 4, "restarts": 3, "chunk_size": CHUNK}
    whole = solve_batch(chain, T, **options, engine="local")
    with pytest.raises(_Crash):
        solve_batch(chain, T, **options, checkpoint=tmp_path, progress=_crash_after(3))
    resumed = solve_batch(chain, T, **options, engine="process", workers=2, checkpoint=tmp_path)
    _assert_identical(resumed, whole)


def test_a_batch_without_a_seed_resumes_with_the_random_streams_it_started_with(problem, tmp_path):
    chain, T = problem
    options = {"seed": None, "restarts": 3, "chunk_size": CHUNK, "engine": "local"}
    first = solve_batch(chain, T, **options, checkpoint=tmp_path)
    fresh = solve_batch(chain, T, **options)
    unreachable = slice(0, None, 25)
    assert not np.array_equal(first.q[unreachable], fresh.q[unreachable])  # another draw
    for file in sorted(tmp_path.glob("chunk-*.npz"))[::2]:
        file.unlink()
    _assert_identical(solve_batch(chain, T, **options, checkpoint=tmp_path), first)


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"T_targets": "moved"}, "targets"),
        ({"q0": "home + 0.1"}, "seeds"),
        ({"seed": 5}, "seed: 5 here, 4 in the checkpoint"),
        ({"restarts": 2}, "restarts: 2 here, 3 in the checkpoint"),
        ({"pos_tol": 1e-7}, "pos_tol"),
        ({"chunk_size": 60}, "chunk_size: 60 here, 50 in the checkpoint"),
        ({"robot": "iiwa14"}, "robot: 'iiwa14' here, 'panda' in the checkpoint"),
    ],
)
def test_a_checkpoint_refuses_another_batch_naming_what_differs(problem, tmp_path, change, named):
    chain, T = problem
    base = {"robot": chain, "T_targets": T, "seed": 4, "restarts": 3, "chunk_size": CHUNK}
    with pytest.raises(_Crash):
        solve_batch(**base, checkpoint=tmp_path, progress=_crash_after(1))
    other = dict(base, **change)
    if change.get("T_targets") == "moved":
        other["T_targets"] = T.copy()
        other["T_targets"][10, 2, 3] += 1e-9  # one coordinate of one target
    if "q0" in change:
        other["q0"] = np.clip(chain.home + 0.1, chain.lower, chain.upper)
    if change.get("robot") == "iiwa14":
        other["robot"] = Chain.from_robot(redik.load("iiwa14"))
    with pytest.raises(CheckpointMismatch, match=named) as refused:
        solve_batch(**other, checkpoint=tmp_path)
    assert str(tmp_path) in str(refused.value)
    assert finished_chunks(tmp_path) == 1  # the checkpoint is left as it was


def test_a_checkpoint_of_another_redik_version_is_refused(problem, tmp_path, monkeypatch):
    chain, T = problem
    options = {"seed": 4, "restarts": 3, "chunk_size": CHUNK}
    solve_batch(chain, T[:60], **options, checkpoint=tmp_path)
    stored = json.loads((tmp_path / FINGERPRINT_FILE).read_text())
    monkeypatch.setattr(checkpoint_module, "redik_version", lambda: "99.0")
    message = f"redik version: '99.0' here, {stored['redik version']!r} in the checkpoint"
    with pytest.raises(CheckpointMismatch, match=message):
        solve_batch(chain, T[:60], **options, checkpoint=tmp_path)


def test_a_write_cut_short_by_a_kill_leaves_no_chunk(problem, tmp_path, solved_chunks):
    chain, T = problem
    options = {"seed": 4, "restarts": 3, "chunk_size": CHUNK, "engine": "local"}
    whole = solve_batch(chain, T, **options)
    with pytest.raises(_Crash):
        solve_batch(chain, T, **options, checkpoint=tmp_path, progress=_crash_after(2))
    # What a kill in the middle of writing chunk 100 leaves: its temporary, never its name.
    torn = tmp_path / ".chunk-000000000100.npz.4242.tmp"
    torn.write_bytes(b"PK\x03\x04 half a zip")
    solved_chunks.clear()
    _assert_identical(solve_batch(chain, T, **options, checkpoint=tmp_path), whole)
    assert solved_chunks == [100, 150, 200, 250]
    assert not torn.exists()


def test_a_chunk_file_that_cannot_be_read_is_named(problem, tmp_path):
    chain, T = problem
    options = {"seed": 4, "restarts": 3, "chunk_size": CHUNK}
    solve_batch(chain, T[:100], **options, checkpoint=tmp_path)
    spoiled = tmp_path / "chunk-000000000050.npz"
    spoiled.write_bytes(b"not a zip")
    with pytest.raises(CheckpointMismatch, match=r"chunk-000000000050\.npz"):
        solve_batch(chain, T[:100], **options, checkpoint=tmp_path)


def test_a_checkpoint_must_be_a_new_or_checkpoint_directory(problem, tmp_path):
    chain, T = problem
    busy = tmp_path / "busy"
    busy.mkdir()
    (busy / "notes.txt").write_text("mine")
    with pytest.raises(CheckpointMismatch, match="not a redik checkpoint"):
        solve_batch(chain, T[:10], checkpoint=busy)
    a_file = tmp_path / "file"
    a_file.write_text("")
    with pytest.raises(redik.InvalidInput, match="must be a directory"):
        solve_batch(chain, T[:10], checkpoint=a_file)
    assert (busy / "notes.txt").read_text() == "mine"

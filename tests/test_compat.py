"""The flat tree's import paths still work for one release (redik/_compat.py)."""

import importlib
import subprocess
import sys

import pytest

import redik
from redik import _compat
from redik.apps import taskspec
from redik.solvers import iterative
from redik.tasks import frame_task

MOVES = {
    "redik.robot": "redik.kinematics.robot",
    "redik.pose_ik": "redik.solvers.pose",
    "redik.solvers.pose_ik": "redik.solvers.pose",
    "redik.solvers.pose_qp": "redik.solvers.pose.qp",
    "redik.batch.chain": "redik.kinematics.chain",
    "redik.analytic.puma": "redik.solvers.analytic.puma",
    "redik.redundancy.plot": "redik.apps.selfmotion_plot",
    "redik.cli": "redik.apps.cli",
}


def test_the_map_takes_the_longest_moved_prefix():
    for old, new in MOVES.items():
        assert _compat.new_name(old) == new
    assert _compat.new_name("redik.batch.solve") == "redik.solvers.batch.solve"
    assert _compat.new_name("redik.lie") is None
    assert _compat.new_name("redik.solvers.pose") is None
    assert _compat.new_name("numpy") is None


def test_old_paths_import_the_new_modules_with_a_warning():
    # A fresh interpreter: this process has imported (some of) the old paths already.
    code = f"""
import importlib, warnings
moves = {MOVES!r}
for old, new in moves.items():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(old)
    assert module is importlib.import_module(new), old
    assert module.__spec__.name == new, module.__spec__
    assert any(new.rsplit(".", 1)[0] in str(w.message) and w.category is DeprecationWarning
               for w in caught), (old, [str(w.message) for w in caught])
import redik
from redik.robot import Robot
assert Robot is redik.Robot
# The functions named like their modules are still the functions.
assert callable(redik.solvers.analytic.puma) and callable(redik.solvers.analytic.ur)
from redik.analytic import puma
assert callable(puma)
print("ok")
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "ok"


def test_names_that_left_redik_still_work_with_a_warning_naming_their_home():
    assert not set(redik._MOVED) & set(redik.__all__)
    for name, (module, attribute) in redik._MOVED.items():
        home = importlib.import_module(module)
        expected = home if attribute is None else getattr(home, attribute)
        with pytest.warns(DeprecationWarning, match=f"redik.{name} is deprecated.*use {module}"):
            assert getattr(redik, name) is expected
    with pytest.raises(AttributeError, match="no attribute 'newtonn'"):
        _ = redik.newtonn


def test_renamed_classes_and_functions_keep_their_old_names_for_one_release():
    for old, new in (("newton", "newton_raphson"), ("gradient", "gradient_descent"),
                     ("hybrid", "gradient_then_newton")):  # fmt: skip
        with pytest.warns(DeprecationWarning, match=f"iterative.{old} is deprecated: it is {new}"):
            assert getattr(iterative, old) is getattr(iterative, new)
        with pytest.warns(DeprecationWarning, match=f"solve_equations\\(..., method='{old}'\\)"):
            assert getattr(redik, old) is getattr(iterative, new)
    with pytest.warns(DeprecationWarning, match="now FrameTargetTask; redik.FrameTask is the pose"):
        assert frame_task.FrameTask is frame_task.FrameTargetTask
    assert issubclass(redik.FrameTask, redik.PoseTask)
    with pytest.warns(DeprecationWarning, match="it is SuccessCriterion"):
        assert taskspec.Criterion is taskspec.SuccessCriterion


def test_the_registry_names_of_the_flat_models_module_still_resolve():
    """``redik.models`` was the third-party registry module; it is now the models package,
    and ``from redik.models import example_robot_data_dir`` (or the tables) failed."""
    import warnings

    import pytest

    from redik.models import registry

    for name in ("EXAMPLE_ROBOT_DATA", "PYBULLET_DATA", "ThirdPartyModel",
                 "example_robot_data_dir", "pybullet_data_dir"):  # fmt: skip
        with pytest.warns(DeprecationWarning, match=f"redik.models.registry.{name}"):
            exec(f"from redik.models import {name} as value", {})
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            import redik.models

            assert getattr(redik.models, name) is getattr(registry, name)
    with pytest.raises(AttributeError):
        redik.models.no_such_name  # noqa: B018


def test_the_corrector_tolerances_keep_their_flat_names():
    """``from redik.redundancy.corrector import POSITION_TOLERANCE`` (the flat tree's name,
    used by its tests) failed after the rename to ``SAMPLE_POSITION_TOLERANCE``."""
    import pytest

    from redik.solvers.redundancy import corrector

    for old, new in (("POSITION_TOLERANCE", "SAMPLE_POSITION_TOLERANCE"),
                     ("ROTATION_TOLERANCE", "SAMPLE_ROTATION_TOLERANCE")):  # fmt: skip
        with pytest.warns(DeprecationWarning, match=new):
            assert getattr(corrector, old) == getattr(corrector, new)

r"""Regression scenes: run every spec and compare it with baselines stored in the repo.

``redik regress`` runs each spec of ``specs/`` (:mod:`redik.apps.specs`), then compares its
metrics with ``specs/baselines/<name>.json`` (one entry per mode, ``fast`` and ``full``).
A spec *regresses* when it crashes, fails one of its own criteria, or a metric moves past
the tolerance of its rule below. ``--update`` rewrites the baselines from the current run.

Which metrics are compared, and how, follows from their names (so a spec author only
returns well-named numbers):

=====================================  ==================  ===================================
metric name                            better              regression when
=====================================  ==================  ===================================
``*success_rate``, ``*_rate``          higher              ``new < base − 0.02``
``*_error`` (final / tracking errors)  lower               ``new > 2·base + 1e-8``
``*iterations*``                       lower               ``new > 1.25·base + 1``
``n_*`` (solutions, samples found)     higher              ``new < base``
``time_ratio`` (added by the runner)   lower               ``new > 3·base + 2``
anything else                          —                   shown, not compared
=====================================  ==================  ===================================

The error rule ignores movement below 1e-8 because converged residuals (1e-12 … 1e-10) move
with the last floating-point rounding, far inside every solver tolerance. ``time_ratio`` is
the spec's wall time divided by the time of a fixed reference workload (MuJoCo kinematics,
Jacobians and a small least-squares solve on a built-in 7-joint chain) measured in the same
run, before and after the specs, so a slower or faster machine leaves it unchanged; the
factor 3 absorbs scheduler noise on loaded CI machines while still catching a solver that
becomes several times slower, and the slack of two reference workloads keeps specs that
take a fraction of a second from flagging jitter. Every spec runs once in fast mode before
anything is timed (:func:`warm_up`), so that a first run's compilation, imports and cache
loads are not part of any spec's time.
"""

from __future__ import annotations

import dataclasses
import gc
import json
import math
import statistics
import tempfile
import time
from collections.abc import Mapping
from pathlib import Path

import mujoco
import numpy as np

from redik.apps.progress import progress_bar
from redik.apps.specs import Context, SpecOutcome, discover, format_table, format_value, run_spec
from redik.core.exceptions import InvalidInput

RATE_DROP = 0.02
ERROR_FACTOR, ERROR_FLOOR = 2.0, 1e-8
ITERATION_FACTOR, ITERATION_SLACK = 1.25, 1.0
TIME_FACTOR, TIME_SLACK = 3.0, 2.0

_REFERENCE_XML = """
<mujoco model="reference_chain">
  <compiler boundmass="0.01" boundinertia="1e-5"/>
  <worldbody>
    <body>
      <joint type="hinge" axis="0 0 1"/>
      <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.04"/>
      <body pos="0 0 0.3"><joint type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
        <body pos="0.3 0 0"><joint type="hinge" axis="1 0 0"/>
          <body pos="0 0 0.3"><joint type="hinge" axis="0 1 0"/>
            <body pos="0.3 0 0"><joint type="hinge" axis="1 0 0"/>
              <body pos="0 0 0.2"><joint type="hinge" axis="0 1 0"/>
                <body pos="0.1 0 0"><joint type="hinge" axis="0 0 1"/>
                  <geom type="sphere" size="0.02"/>
                  <site name="ee" pos="0 0 0.1"/>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def reference_seconds(repeats: int = 3, evaluations: int = 1000) -> float:
    """Median time of the reference workload: ``evaluations`` × (FK, Jacobian, lstsq).

    The workload mixes what specs spend their time on — MuJoCo calls through the
    Python bindings and small dense linear algebra — so the ratio of a spec's time to it is
    about constant across machines.
    """
    model = mujoco.MjModel.from_xml_string(_REFERENCE_XML)
    data = mujoco.MjData(model)
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    J = np.empty((6, model.nv))
    rng = np.random.default_rng(0)
    qs = rng.uniform(-np.pi, np.pi, size=(evaluations, model.nq))
    e = np.ones(6)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        for q in qs:
            data.qpos[:] = q
            mujoco.mj_kinematics(model, data)
            mujoco.mj_comPos(model, data)
            mujoco.mj_jacSite(model, data, jacp, jacr, 0)
            J[:3], J[3:] = jacp, jacr
            np.linalg.lstsq(J, e, rcond=None)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


@dataclasses.dataclass(frozen=True)
class Comparison:
    """One metric of one spec against its baseline.

    ``status`` is ``"ok"``, ``"REGRESSED"``, ``"improved"``, ``"new"`` (no baseline value)
    or ``"info"`` (no rule for this metric name).
    """

    metric: str
    baseline: float | None
    value: float | None
    tolerance: str
    status: str


def _rule(metric: str) -> tuple[str, str] | None:
    """``(direction, tolerance text)`` for a metric name, or None when it is not compared."""
    if metric == "time_ratio":
        return "lower", f"≤ {TIME_FACTOR:g}·base + {TIME_SLACK:g}"
    if metric.endswith("_rate"):
        return "higher", f"≥ base − {RATE_DROP:g}"
    if metric.endswith("_error"):
        return "lower", f"≤ {ERROR_FACTOR:g}·base + {ERROR_FLOOR:g}"
    if "iterations" in metric:
        return "lower", f"≤ {ITERATION_FACTOR:g}·base + {ITERATION_SLACK:g}"
    if metric.startswith("n_"):
        return "higher", "≥ base"
    return None


def _regressed(metric: str, value: float, base: float) -> bool:
    if math.isnan(value):
        return True
    if metric == "time_ratio":
        return value > TIME_FACTOR * base + TIME_SLACK
    if metric.endswith("_rate"):
        return value < base - RATE_DROP
    if metric.endswith("_error"):
        return value > ERROR_FACTOR * base + ERROR_FLOOR
    if "iterations" in metric:
        return value > ITERATION_FACTOR * base + ITERATION_SLACK
    if metric.startswith("n_"):
        return value < base
    return False


def compare(metrics: Mapping[str, float], baseline: Mapping[str, float]) -> list[Comparison]:
    """Compare current ``metrics`` with ``baseline`` by the rules of this module."""
    comparisons = []
    for metric in sorted(set(metrics) | set(baseline)):
        value, base = metrics.get(metric), baseline.get(metric)
        rule = _rule(metric)
        if rule is None:
            comparisons.append(Comparison(metric, base, value, "", "info"))
            continue
        direction, tolerance = rule
        if value is None:
            status = "REGRESSED"  # a compared metric the spec no longer reports
        elif base is None:
            status = "new"
        elif _regressed(metric, value, base):
            status = "REGRESSED"
        elif (value > base) if direction == "higher" else (value < base):
            status = "improved"
        else:
            status = "ok"
        comparisons.append(Comparison(metric, base, value, tolerance, status))
    return comparisons


@dataclasses.dataclass
class SpecRegression:
    """One spec's run, its time ratio and its comparisons with the baseline."""

    outcome: SpecOutcome
    time_ratio: float
    comparisons: list[Comparison]
    has_baseline: bool

    @property
    def regressed(self) -> bool:
        """True when the spec failed its own criteria or a metric moved past tolerance."""
        return not self.outcome.passed or any(c.status == "REGRESSED" for c in self.comparisons)


@dataclasses.dataclass
class RegressionReport:
    """Everything one ``redik regress`` run measured."""

    specs: list[SpecRegression]
    reference_seconds: float
    fast: bool
    updated: list[Path] = dataclasses.field(default_factory=list)

    @property
    def regressed(self) -> bool:
        """True when any spec regressed (crashed, failed a criterion or moved a metric)."""
        return any(spec.regressed for spec in self.specs)

    def table(self) -> str:
        """The per-metric table printed by ``redik regress``."""
        rows = []
        for spec in self.specs:
            verdict = (
                "crashed"
                if spec.outcome.error
                else "criteria " + ("ok" if spec.outcome.passed else "FAILED")
            )
            if not spec.has_baseline:
                verdict += ", no baseline"
            rows.append([spec.outcome.name, f"({verdict})", "", "", "", ""])
            for c in spec.comparisons:
                values = [format_value(c.baseline), format_value(c.value)]
                rows.append(["", c.metric, *values, c.tolerance, c.status])
            for check in spec.outcome.checks:
                if not check.passed:
                    value = format_value(check.value)
                    rows.append(
                        ["", check.criterion.metric, "", value, str(check.criterion), "FAIL"]
                    )
        mode = "fast" if self.fast else "full"
        head = (
            f"redik regress ({mode}): {len(self.specs)} specs, reference workload "
            f"{self.reference_seconds * 1e3:.1f} ms"
        )
        table = format_table(["spec", "metric", "baseline", "now", "tolerance", "status"], rows)
        failed = [s.outcome.name for s in self.specs if s.regressed]
        tail = f"REGRESSED: {', '.join(failed)}" if failed else "no regression"
        errors = [
            f"--- {s.outcome.name} ---\n{s.outcome.error}" for s in self.specs if s.outcome.error
        ]
        return "\n".join([head, table, *errors, tail])


def default_specs_dir() -> Path:
    """The repository's ``specs/`` folder (next to the package), else ``./specs``."""
    beside_package = Path(__file__).resolve().parents[2] / "specs"
    return beside_package if beside_package.is_dir() else Path("specs")


def baseline_path(baselines_dir: Path, name: str) -> Path:
    """The baseline file of spec ``name``: ``<baselines_dir>/<name>.json``."""
    return Path(baselines_dir) / f"{name}.json"


def load_baseline(path: Path, mode: str) -> dict[str, float] | None:
    """The stored metrics (with ``time_ratio``) of one mode, or None when absent."""
    if not path.is_file():
        return None
    try:
        entry = json.loads(path.read_text()).get(mode)
    except json.JSONDecodeError as error:
        raise InvalidInput(f"baseline {str(path)!r} is not valid JSON: {error}") from None
    if entry is None:
        return None
    return {**entry["metrics"], "time_ratio": entry["time_ratio"]}


def write_baseline(path: Path, outcome: SpecOutcome, time_ratio: float) -> None:
    """Store ``outcome``'s metrics under its mode, keeping the other mode's entry."""
    path.parent.mkdir(parents=True, exist_ok=True)
    stored = json.loads(path.read_text()) if path.is_file() else {}
    stored["spec"] = outcome.name
    stored["fast" if outcome.fast else "full"] = {
        "metrics": outcome.metrics,
        "time_ratio": float(f"{time_ratio:.4g}"),
        "seconds": float(f"{outcome.seconds:.4g}"),
    }
    path.write_text(json.dumps(stored, indent=2, sort_keys=True) + "\n")


def warm_up(paths: list[Path], seed: int, scratch: Path) -> None:
    """Run every spec once, in fast mode and untimed, before anything is timed.

    A spec's first run in a process pays costs of the machine, not of the spec: numba kernels
    compiled (once per machine, and again after an edit to a module a kernel imports,
    :mod:`redik.core.kernel_cache`) or loaded from the disk cache, modules imported on first
    use, ``solve_batch``'s process pool started. They must not land in a spec's time ratio.
    The fast mode calls the same kernels as the full one; a crash here is reported by the
    timed run.
    """
    for path in paths:
        run_spec(path, Context(fast=True, seed=seed, out=scratch / "warm-up" / path.stem))


def run_regression(
    specs_dir: str | Path | None = None,
    baselines_dir: str | Path | None = None,
    *,
    fast: bool = False,
    update: bool = False,
    seed: int = 0,
    out: str | Path | None = None,
    show_progress: bool = False,
) -> RegressionReport:
    """Run every spec of ``specs_dir`` and compare it with ``baselines_dir``.

    Args:
        specs_dir: Folder of specs (default :func:`default_specs_dir`).
        baselines_dir: Folder of baseline JSON files (default ``specs_dir/baselines``).
        fast: Run the specs in fast mode (and compare with the ``fast`` baselines).
        update: Rewrite the baselines of every spec that passed its own criteria.
        seed: Passed to every spec's :class:`~redik.apps.specs.Context`.
        out: Folder for the specs' pictures (default: a temporary folder, discarded).
        show_progress: Draw a progress bar on stderr: the warm-up, the reference timing and
            each spec by name (and the specs' own bars, :meth:`Context.progress`).
    """
    specs_dir = Path(specs_dir) if specs_dir is not None else default_specs_dir()
    baselines_dir = Path(baselines_dir) if baselines_dir is not None else specs_dir / "baselines"
    paths = discover(specs_dir)
    mode = "fast" if fast else "full"
    # Steps: the warm-up, a reference timing before and after, and every spec.
    progress = progress_bar(
        total=len(paths) + 3, desc="regress", unit="step", enabled=show_progress
    )
    with progress, tempfile.TemporaryDirectory(prefix="redik-regress-") as scratch:
        progress.set_postfix_str("warm-up: every spec once, untimed")
        warm_up(paths, seed, Path(scratch))
        # Compiling leaves hundreds of thousands of objects behind; the first full collection
        # would traverse them all inside whichever spec triggers it. Collected and frozen
        # here, the collections during the specs see only the specs' own objects.
        gc.collect()
        gc.freeze()
        progress.update()
        out_root = Path(out) if out is not None else Path(scratch)
        try:
            progress.set_postfix_str("reference timing")
            before = reference_seconds()
            progress.update()
            outcomes = []
            for path in paths:
                progress.set_postfix_str(path.stem)
                context = Context(
                    fast=fast, seed=seed, out=out_root / path.stem, show_progress=show_progress
                )
                outcomes.append(run_spec(path, context))
                progress.update()
            progress.set_postfix_str("reference timing")
            reference = 0.5 * (before + reference_seconds())
            progress.update()
        finally:
            gc.unfreeze()

    report = RegressionReport(specs=[], reference_seconds=reference, fast=fast)
    for outcome in outcomes:
        time_ratio = outcome.seconds / reference
        path = baseline_path(baselines_dir, outcome.name)
        baseline = load_baseline(path, mode)
        metrics = {**outcome.metrics, "time_ratio": time_ratio} if not outcome.error else {}
        comparisons = compare(metrics, baseline or {}) if not outcome.error else []
        report.specs.append(SpecRegression(outcome, time_ratio, comparisons, baseline is not None))
        if update and outcome.passed:
            write_baseline(path, outcome, time_ratio)
            report.updated.append(path)
    return report

r"""Specs: plain Python files that say what redik should do and what success means.

A spec is a module (``specs/<name>.py``) with three things::

    '''Panda reach with joint-limit avoidance.'''     # first line: the description

    CRITERIA = {"success_rate": ">= 1.0", "max_position_error": "<= 1e-6"}

    def run(ctx):                                      # ctx: a :class:`Context`
        robot = redik.load("panda")
        ...
        return {"success_rate": ..., "max_position_error": ...}   # metrics: name → number

``run`` builds its scene, task stack and targets (or trajectory), does the work and returns
its metrics as plain numbers. ``CRITERIA`` maps a metric name to a comparison
(``">= 1"``, ``"<= 1e-6"``, ``"== 8"``, ``"< x"``, ``"> x"``); a spec *passes* when every
criterion holds. The spec's name is the file stem.

The :class:`Context` carries what a spec may vary on: ``ctx.fast`` (a few seconds, used by
``make test``; :meth:`Context.size` picks a workload size by mode), ``ctx.seed`` and
``ctx.rng`` for reproducible randomness, ``ctx.out`` (a folder for pictures and data) and
``ctx.progress`` (a tqdm bar when the runner shows one).

:func:`run_spec` runs one spec and never raises for a failing or crashing spec: the outcome
is data (:class:`SpecOutcome`), like every redik result. ``redik run specs/<file>.py`` is the
command-line front end; :mod:`redik.apps.regress` compares outcomes against stored baselines.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import operator
import re
import time
import traceback
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from redik.core.exceptions import InvalidInput
from redik.kinematics.robot import Robot

T = TypeVar("T")

_COMPARISONS: dict[str, Callable[[float, float], bool]] = {
    ">=": operator.ge,
    "<=": operator.le,
    "==": operator.eq,
    ">": operator.gt,
    "<": operator.lt,
}
_CRITERION = re.compile(r"^\s*(>=|<=|==|>|<)\s*([-+0-9.eE]+|inf|-inf)\s*$")


@dataclasses.dataclass(frozen=True)
class SuccessCriterion:
    """One success condition ``metric OP threshold`` of a spec's ``CRITERIA``.

    For example ``max_position_error <= 1e-6``. (Not :class:`redik.solvers.redundancy.Criterion`,
    a score of configurations.)
    """

    metric: str
    op: str
    threshold: float

    @classmethod
    def parse(cls, metric: str, text: str | float) -> SuccessCriterion:
        """From ``">= 0.99"``-style text; a bare number means ``== number``.

        Raises:
            InvalidInput: the text is not ``OP NUMBER`` with OP one of ``>= <= == > <``.
        """
        if isinstance(text, (int, float)) and not isinstance(text, bool):
            return cls(metric, "==", float(text))
        match = _CRITERION.match(str(text))
        if match is None:
            raise InvalidInput(
                f"criterion for {metric!r} must look like '>= 0.99' or '<= 1e-6' "
                f"(operators {list(_COMPARISONS)}), got {text!r}"
            )
        return cls(metric, match.group(1), float(match.group(2)))

    def holds(self, value: float | None) -> bool:
        """True when ``value`` satisfies the condition; a missing or NaN value never does."""
        if value is None or math.isnan(value):
            return False
        return _COMPARISONS[self.op](value, self.threshold)

    def __str__(self) -> str:
        return f"{self.op} {self.threshold:g}"


@dataclasses.dataclass
class Spec:
    """A runnable task: a name, a ``run(ctx) -> metrics`` callable and its criteria.

    Usually built by :func:`load_spec` from a file; construct one directly to run a spec
    defined in code.
    """

    name: str
    run: Callable[[Context], Mapping[str, float]]
    criteria: Mapping[str, str | float] = dataclasses.field(default_factory=dict)
    description: str = ""
    path: Path | None = None
    parsed_criteria: list[SuccessCriterion] = dataclasses.field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not callable(self.run):
            raise InvalidInput(f"spec {self.name!r}: run must be callable, got {self.run!r}")
        self.parsed_criteria = [SuccessCriterion.parse(k, v) for k, v in self.criteria.items()]


@dataclasses.dataclass
class Context:
    """What a running spec may read: mode, seed, output folder and a progress wrapper.

    Attributes:
        fast: True for the few-seconds mode (``--fast``, ``make test``).
        seed: The seed every random choice of the spec derives from.
        out: A folder for the spec's pictures and data (created on demand by :meth:`path`).
        show_progress: Whether :meth:`progress` draws a tqdm bar.
    """

    fast: bool = False
    seed: int = 0
    out: Path = dataclasses.field(default_factory=lambda: Path("out") / "specs")
    show_progress: bool = False

    def __post_init__(self) -> None:
        self.out = Path(self.out)
        self.rng = np.random.default_rng(self.seed)

    def size(self, full: int, fast: int) -> int:
        """The workload size for this mode: ``fast`` in fast mode, else ``full``."""
        return fast if self.fast else full

    def path(self, filename: str) -> Path:
        """``out/filename``, creating the output folder."""
        self.out.mkdir(parents=True, exist_ok=True)
        return self.out / filename

    def progress(
        self, iterable: Iterable[T], total: int | None = None, desc: str | None = None
    ) -> Iterator[T]:
        """Iterate ``iterable``, drawing a progress bar (stderr) when asked to."""
        if not self.show_progress:
            yield from iterable
            return
        from redik.apps.progress import progress_bar  # only the interactive runner needs tqdm

        yield from progress_bar(iterable, total=total, desc=desc, leave=False)


@dataclasses.dataclass(frozen=True)
class CriterionCheck:
    """A criterion with the value it was checked against."""

    criterion: SuccessCriterion
    value: float | None
    passed: bool


@dataclasses.dataclass
class SpecOutcome:
    """The result of running one spec.

    Attributes:
        name: The spec's name.
        metrics: The metrics ``run`` returned (empty when it raised).
        checks: One :class:`CriterionCheck` per criterion.
        passed: True when ``run`` finished and every criterion holds.
        seconds: Wall-clock time of ``run``.
        error: The traceback when ``run`` raised, else None.
        fast: The mode it ran in.
    """

    name: str
    metrics: dict[str, float]
    checks: list[CriterionCheck]
    passed: bool
    seconds: float
    error: str | None = None
    fast: bool = False
    description: str = ""


def load_spec(path: str | Path) -> Spec:
    """Import a spec file and return its :class:`Spec`.

    The module must define ``run(ctx)`` and may define ``CRITERIA`` (a dict); its name is
    the file stem and its description the first line of its docstring.

    Raises:
        InvalidInput: the file is missing or does not define ``run``.
    """
    path = Path(path)
    if not path.is_file():
        raise InvalidInput(f"spec file not found: {str(path)!r}")
    module_name = f"redik_task_{path.stem}_{abs(hash(path.resolve()))}"
    loader_spec = importlib.util.spec_from_file_location(module_name, path)
    if loader_spec is None or loader_spec.loader is None:
        raise InvalidInput(f"cannot import spec {str(path)!r} (not a Python file?)")
    module = importlib.util.module_from_spec(loader_spec)
    loader_spec.loader.exec_module(module)
    run = getattr(module, "run", None)
    if run is None:
        raise InvalidInput(f"spec {str(path)!r} defines no run(ctx) function")
    criteria = getattr(module, "CRITERIA", {})
    if not isinstance(criteria, Mapping):
        raise InvalidInput(
            f"spec {str(path)!r}: CRITERIA must be a dict of metric -> '>= x', "
            f"got {type(criteria).__name__}"
        )
    description = (module.__doc__ or "").strip().splitlines()
    return Spec(
        name=path.stem,
        run=run,
        criteria=dict(criteria),
        description=description[0] if description else "",
        path=path,
    )


def discover(folder: str | Path) -> list[Path]:
    """The spec files of a folder (``*.py`` not starting with ``_``), sorted."""
    folder = Path(folder)
    if not folder.is_dir():
        raise InvalidInput(f"task folder not found: {str(folder)!r}")
    return sorted(p for p in folder.glob("*.py") if not p.name.startswith("_"))


def run_spec(spec: Spec | str | Path, context: Context | None = None) -> SpecOutcome:
    """Run one spec and check its criteria; a crash becomes a failed outcome, not an error."""
    if not isinstance(spec, Spec):
        spec = load_spec(spec)
    context = context or Context()
    start = time.perf_counter()
    error = None
    metrics: dict[str, float] = {}
    try:
        returned = spec.run(context)
        if not isinstance(returned, Mapping):
            raise InvalidInput(
                f"spec {spec.name!r}: run must return a dict of metrics, "
                f"got {type(returned).__name__}"
            )
        metrics = {str(k): float(v) for k, v in returned.items()}
    except Exception:  # a spec is user code: report its failure as data
        error = traceback.format_exc()
    seconds = time.perf_counter() - start
    checks = [
        CriterionCheck(c, metrics.get(c.metric), c.holds(metrics.get(c.metric)))
        for c in spec.parsed_criteria
    ]
    return SpecOutcome(
        name=spec.name,
        metrics=metrics,
        checks=checks,
        passed=error is None and all(check.passed for check in checks),
        seconds=seconds,
        error=error,
        fast=context.fast,
        description=spec.description,
    )


def sample_poses(
    robot: Robot, rng: np.random.Generator, count: int, min_sigma: float = 0.0
) -> list[np.ndarray]:
    """End-effector poses of random joint values (uniform in the limits) — reachable targets.

    With ``min_sigma > 0`` configurations where ``σ_min`` of the world Jacobian is below it
    are redrawn: near a singularity a pose tolerance of 1e-6 m admits joint errors far above
    1e-4 rad, so comparing solutions branch by branch there would test the tolerance, not
    the solvers.
    """
    poses: list[np.ndarray] = []
    while len(poses) < count:
        q = robot.random_q(rng)
        if (
            min_sigma <= 0.0
            or np.linalg.svd(robot.jacobian(q, reference="world"), compute_uv=False)[-1]
            >= min_sigma
        ):
            poses.append(robot.fk(q))
    return poses


def format_value(value: float | None) -> str:
    """A metric value in a table: integers plainly, other numbers to 4 significant digits."""
    if value is None:
        return "—"
    if math.isfinite(value) and value == int(value) and abs(value) < 1e9:
        return str(int(value))
    return f"{value:.4g}"


def format_table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A plain-text table with columns padded to their widest cell."""
    cells = [[str(h) for h in headers], *[[str(c) for c in row] for row in rows]]
    widths = [max(len(row[i]) for row in cells) for i in range(len(headers))]
    lines = [
        "  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip()
        for row in cells
    ]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def summary_table(outcome: SpecOutcome) -> str:
    """The summary printed by ``redik run``: every metric, its criterion and the verdict."""
    criteria = {check.criterion.metric: check for check in outcome.checks}
    rows = []
    for metric, value in outcome.metrics.items():
        check = criteria.pop(metric, None)
        verdict = "" if check is None else ("ok" if check.passed else "FAIL")
        criterion = "" if check is None else str(check.criterion)
        rows.append([metric, format_value(value), criterion, verdict])
    for metric, check in criteria.items():  # criteria whose metric was never returned
        rows.append([metric, "missing", str(check.criterion), "FAIL"])
    mode = "fast" if outcome.fast else "full"
    verdict = "PASSED" if outcome.passed else "FAILED"
    title = f"{outcome.name} ({mode}, {outcome.seconds:.2f} s): {verdict}"
    if outcome.description:
        title += f" — {outcome.description}"
    text = title + "\n" + format_table(["metric", "value", "criterion", ""], rows)
    if outcome.error:
        text += "\n" + outcome.error.rstrip()
    return text

"""What the explorer's growth mixins read from the explorer they are mixed into."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

    from redik.solvers.redundancy.corrector import BatchCorrector, Corrector
    from redik.solvers.redundancy.selfmotion.index import SampleIndex


class ExplorerPart:
    """Base of :class:`~.covering.SurfaceCovering` and :class:`~.tracing.CurveTracing`.

    It has no behaviour: it declares, for the type checker, the explorer's state and methods
    that the mixins use (:class:`~redik.solvers.redundancy.selfmotion.explore.Explorer`
    provides them).
    """

    if TYPE_CHECKING:
        corrector: Corrector
        spacing: float
        periodic: np.ndarray
        torus: np.ndarray
        traced: SampleIndex
        batch: BatchCorrector
        exact_curves: list[np.ndarray]

        @property
        def budget(self) -> int:
            """Samples still allowed."""

        def distance(self, a: np.ndarray, b: np.ndarray) -> float:
            """The joint-space distance of two configurations, periodic joints modulo 2π."""

        def _append(
            self, part: np.ndarray | list[np.ndarray], closed: bool, ends: tuple[str, ...]
        ) -> None: ...

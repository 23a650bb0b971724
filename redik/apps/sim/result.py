"""What a closed-loop run recorded: :class:`SimulationResult`, its status and its contacts."""

from __future__ import annotations

import dataclasses
from enum import Enum

import numpy as np

from redik.core.exceptions import InvalidInput

LISTED_CONTACTS = 5
"""Contacts named in a summary (the deepest first); the result holds them all."""


class SimulationStatus(str, Enum):
    """How a run of :func:`~redik.apps.sim.simulate` ended.

    A ``str``-valued enum, like :class:`redik.Status`: ``result.status == "completed"`` holds.

    ==============  ============================================================================
    ``COMPLETED``   Every tick of the requested duration ran. Whether the tracking was good is
                    a separate question (:attr:`SimulationResult.within_bound`).
    ``UNSTABLE``    MuJoCo reported the physics unsound during a tick (a ``mjtWarning``): a
                    NaN, inf or huge value in ``qpos``, ``qvel``, ``qacc`` (MuJoCo then resets
                    the state to ``qpos0``) or in the controls, or a constraint or contact
                    arena so full that constraints were dropped. The run stopped; the result
                    holds the ticks before that one, and :attr:`SimulationResult.message`
                    names the warning, the joint or actuator and the tick.
    ==============  ============================================================================
    """

    COMPLETED = "completed"
    UNSTABLE = "unstable"

    def __str__(self) -> str:
        return self.value

    def __format__(self, spec: str) -> str:
        return format(self.value, spec)


@dataclasses.dataclass(frozen=True)
class Contact:
    """Two bodies that touched during a run: which, when and how deep.

    MuJoCo's contacts of each tick's last physics step are read (those with a signed distance
    ``dist ≤ 0``: touching or interpenetrating) and grouped by body pair.

    Attributes:
        body1: The robot's body (the first of the two by id for a contact within the robot).
        body2: The other body: another robot body, or a body of the world (``"world"`` for
            geoms fixed in the world, or a body of another tree such as a table or an object).
        kind: ``"self"`` when both bodies belong to the robot's kinematic trees, ``"world"``
            when one does not.
        times: ``(k,)`` times of the ticks at which the two touched.
        depth: ``(k,)`` the pair's deepest penetration ``−dist`` at each of those ticks, metres
            (0 for a contact that only touches).
    """

    body1: str
    body2: str
    kind: str
    times: np.ndarray
    depth: np.ndarray

    @property
    def first(self) -> float:
        """Time of the first tick in contact (s)."""
        return float(self.times[0])

    @property
    def last(self) -> float:
        """Time of the last tick in contact (s)."""
        return float(self.times[-1])

    @property
    def max_depth(self) -> float:
        """Deepest penetration over the run (m)."""
        return float(self.depth.max())

    def describe(self) -> str:
        """One phrase: ``"self link0–link1 0.01–4.00 s (400 ticks), deepest 1.20 mm"``."""
        span = (
            f"{self.first:.2f} s" if len(self.times) == 1 else f"{self.first:.2f}–{self.last:.2f} s"
        )
        return (
            f"{self.kind} {self.body1}–{self.body2} {span} ({len(self.times)} ticks), "
            f"deepest {self.max_depth * 1e3:.2f} mm"
        )


@dataclasses.dataclass
class SimulationResult:
    """What a closed-loop run recorded, one row per control tick.

    Attributes:
        times: (N,) tick times in seconds (each row is the state once the physics reached it).
        q: (N, n) measured chain joint values.
        q_command: (N, n) joint references ``q̂`` the actuators tracked.
        qpos: (N, nq) full simulation state, for rendering the run afterwards.
        targets: (N, 4, 4) reference poses.
        position_error: (N,) ``‖p_d − p‖`` of the simulated end-effector, metres.
        rotation_error: (N,) angle of ``Rᵀ R_d``, radians.
        control_rate: Control ticks per second.
        reference_position_error: (N,) the same for the FK of ``q̂``: the IK's own share.
        reference_rotation_error: (N,) likewise, radians.
        saturated: (N,) True where a control was clipped to its ``ctrlrange`` or an
            actuator force to its ``forcerange`` during the tick.
        drives: The kind of actuator driving each chain joint (``"position"``/``"motor"``).
        error_bound: ``(position m, rotation rad)`` the run was checked against, or None.
        status: How the run ended (:class:`SimulationStatus`); ``N`` is the number of ticks
            requested when it completed, fewer when it stopped.
        message: Why the run stopped (empty when it completed).
        contacts: Every body pair that touched, robot with robot or robot with the world,
            deepest first (:class:`Contact`).
        held_base: Name of the free joint held at its initial pose (``hold_base=True``), or "".
    """

    times: np.ndarray
    q: np.ndarray
    q_command: np.ndarray
    qpos: np.ndarray
    targets: np.ndarray
    position_error: np.ndarray
    rotation_error: np.ndarray
    control_rate: float
    reference_position_error: np.ndarray | None = None
    reference_rotation_error: np.ndarray | None = None
    saturated: np.ndarray | None = None
    drives: tuple[str, ...] = ()
    error_bound: tuple[float, float] | None = None
    status: SimulationStatus = SimulationStatus.COMPLETED
    message: str = ""
    contacts: tuple[Contact, ...] = ()
    held_base: str = ""

    @property
    def max_position_error(self) -> float:
        """Largest position error over the recorded ticks (m; NaN when none was recorded)."""
        return _largest(self.position_error)

    @property
    def max_rotation_error(self) -> float:
        """Largest rotation error over the recorded ticks (rad; NaN when none)."""
        return _largest(self.rotation_error)

    @property
    def rms_position_error(self) -> float:
        """Root mean square of the position error (m; NaN when no tick was recorded)."""
        return _rms(self.position_error)

    @property
    def rms_rotation_error(self) -> float:
        """Root mean square of the rotation error (rad; NaN when no tick was recorded)."""
        return _rms(self.rotation_error)

    @property
    def final_position_error(self) -> float:
        """Position error at the last recorded tick (m; NaN when none)."""
        return float(self.position_error[-1]) if len(self.position_error) else float("nan")

    @property
    def final_rotation_error(self) -> float:
        """Rotation error at the last recorded tick (rad; NaN when none)."""
        return float(self.rotation_error[-1]) if len(self.rotation_error) else float("nan")

    @property
    def saturation_fraction(self) -> float:
        """Fraction of ticks during which an actuator saturated."""
        if self.saturated is None or len(self.saturated) == 0:
            return 0.0
        return float(np.mean(self.saturated))

    @property
    def within_bound(self) -> bool:
        """True when no recorded tick left the reference by more than :attr:`error_bound`.

        Always True without a bound; see :attr:`success` for a run that also completed.
        """
        if self.error_bound is None or len(self.times) == 0:
            return self.error_bound is None
        position, rotation = self.error_bound
        return self.max_position_error <= position and self.max_rotation_error <= rotation

    @property
    def success(self) -> bool:
        """The run completed and stayed within :attr:`error_bound` (when one was set)."""
        return self.status is SimulationStatus.COMPLETED and self.within_bound

    def summary(self) -> str:
        """One line: how the run ended, the tracking errors, saturation and contacts."""
        parts = (
            [] if self.status is SimulationStatus.COMPLETED else [f"{self.status}: {self.message}"]
        )
        parts.append(self._tracking() if len(self.times) else "no tick recorded")
        if self.saturation_fraction > 0.0:
            parts.append(f"actuators saturated in {100 * self.saturation_fraction:.1f} % of ticks")
        if self.contacts:
            parts.append(self.contact_summary())
        return "; ".join(parts)

    def contact_summary(self) -> str:
        """``"contacts: …"``, the deepest :data:`LISTED_CONTACTS` pairs ('' when none)."""
        if not self.contacts:
            return ""
        listed = ", ".join(c.describe() for c in self.contacts[:LISTED_CONTACTS])
        more = len(self.contacts) - LISTED_CONTACTS
        return f"contacts: {listed}" + (f" and {more} more pairs" if more > 0 else "")

    def _tracking(self) -> str:
        """The tick count and the tracking errors (max, rms, final; the IK's own share)."""
        line = (
            f"{len(self.times)} ticks at {self.control_rate:g} Hz over {self.times[-1]:.2f} s: "
            f"tracking error max {self.max_position_error * 1e3:.3f} mm / "
            f"{self.max_rotation_error:.2e} rad, rms {self.rms_position_error * 1e3:.3f} mm / "
            f"{self.rms_rotation_error:.2e} rad, final {self.final_position_error * 1e3:.4f} mm"
            f" / {self.final_rotation_error:.2e} rad"
        )
        if self.reference_position_error is not None and self.reference_rotation_error is not None:
            line += (
                f"; IK reference alone max {self.reference_position_error.max() * 1e3:.3f} mm"
                f" / {self.reference_rotation_error.max():.2e} rad"
            )
        return line


def tracking_diagnosis(name: str, result: SimulationResult) -> str:
    """The :class:`~redik.core.exceptions.TrackingWarning` message: the errors, and the blame.

    The IK is blamed when its own reference leaves the path by more than half the bound;
    saturation and contacts are named when they happened.
    """
    if result.error_bound is None:
        raise InvalidInput("tracking_diagnosis needs a result checked against an error_bound")
    position, rotation = result.error_bound
    message = (
        f"{name}: tracking error exceeds the bound {position * 1e3:g} mm / {rotation:g} rad: "
        f"{result.summary()}."
    )
    reference = (result.reference_position_error, result.reference_rotation_error)
    if (reference[0] is not None and reference[0].max() > 0.5 * position) or (
        reference[1] is not None and reference[1].max() > 0.5 * rotation
    ):
        message += (
            " The IK reference itself leaves the path: the QP cannot follow it there (a "
            "singularity, a joint or velocity limit); change the path, the start posture or "
            "the limits."
        )
    if result.saturation_fraction > 0.0:
        message += (
            " Actuators saturated (ctrlrange or forcerange): the servos could not apply the "
            "torque the motion needs."
        )
    if result.contacts:
        message += (
            " Bodies touched (see contacts above): a contact can hold the robot off its path; "
            "keep them apart (a CollisionAvoidanceLimit) or exclude the pair in the model."
        )
    return message


def _largest(values: np.ndarray) -> float:
    return float(values.max()) if len(values) else float("nan")


def _rms(values: np.ndarray) -> float:
    return float(np.sqrt(np.mean(values**2))) if len(values) else float("nan")

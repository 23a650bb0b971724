r"""Inverse kinematics of a :class:`~redik.kinematics.robot.Robot` to a pose target in SE(3).

One idea per module:

- :mod:`~redik.solvers.pose.solve`: the entry points :func:`solve_pose` and :func:`solve_all`
  (validation, dispatch, restarts, whole-model robots);
- :mod:`~redik.solvers.pose.options`: the methods, their defaults and option checks;
- :mod:`~redik.solvers.pose.dls_solver`: the ``"dls"`` driver around the compiled kernel;
- :mod:`~redik.solvers.pose.attempt`: one attempt of ``"newton"``, ``"transpose"`` or
  ``"hybrid"``: the loops of :mod:`redik.solvers.iterative` on the pose residual
  (:class:`~redik.solvers.iterative.PoseResidual`);
- :mod:`~redik.solvers.pose.result`: the result, its status and the unreachable diagnosis;
- :mod:`~redik.solvers.pose.frame`, :mod:`~redik.solvers.pose.cache`: what solves of one
  frame share (moving joints, reach, the compiled solver), kept by the robot;
- :mod:`~redik.solvers.pose.qp`: the ``"qp"`` driver on :class:`redik.Problem`;
- :mod:`~redik.solvers.pose.closed_form`: ``solve_all(method="analytic")``, every solution
  of the robot's closed-form solver (:mod:`redik.solvers.analytic`) as results.

:func:`solve_pose` validates its inputs once (a ``"dls"`` call whose scalar arguments it
has seen before leaves the target and ``q0`` to the compiled kernel, which checks them), then
runs one of the methods below (one :meth:`Robot.kinematics` call — FK and world Jacobian —
per trial; ``"dls"`` entirely in compiled code), restarting from random configurations when
an attempt fails. Success is always decided by a fresh FK of the
returned ``q``: MuJoCo's, or for ``"dls"`` the compiled chain's (equal to MuJoCo's to 1e-12,
``tests/test_batch_kernel.py``; MuJoCo's again when ``q`` was shifted into the limits).
:func:`solve_all` collects the distinct solutions found from many starts. Frames, twist
order ``(v, ω)`` and Jacobian references are those of :mod:`redik.core.conventions`.

The methods:
    ``"newton"``
        Modern Robotics' *IKinBody* (Lynch & Park §6.2.2): the body error twist
        ``V_b = log(T_sb⁻¹ T_sd)`` and ``q ← q + J_b⁺ V_b``. With ``form="space"`` it is the
        space form (*IKinSpace*), ``V_s = Ad_{T_sb} V_b`` and ``q ← q + J_s⁺ V_s``.
        Stopping rule (``stop``): ``"pose"`` (default) stops when ``‖p_d − p‖ ≤ pos_tol`` and
        ``angle(Rᵀ R_d) ≤ rot_tol`` — the success test of every method, so Newton stops as
        soon as the result is certain to succeed; ``"twist"`` is the book's rule
        (Algorithm IKinBody/IKinSpace): ``‖ω‖ ≤ ε_ω = rot_tol`` and ``‖v‖ ≤ ε_v = pos_tol`` of
        the error twist ``(v, ω)`` of the form in use. The two differ only in the linear
        part: ``Rᵀ(p_d − p) = (G(θ)/θ) v_b`` (MR §3.3.3, the exponential of se(3)), whose
        singular values are 1 (along the rotation axis) and ``2 sin(θ/2)/θ ≤ 1``, so
        ``‖p_d − p‖ ≤ ‖v_b‖``. The body twist rule is thus the stricter, by up to
        ``θ / (2 sin(θ/2)) ≤ π/2`` across the axis of the rotation error ``θ``: it mixes the
        rotation error into the position test, and ``‖v_s‖`` also grows with the distance
        of the frame from the world origin. The default is the pose rule because
        ``pos_tol`` and ``rot_tol`` then mean the same thing for every method; success is
        decided by the pose test with either rule.
    ``"transpose"``
        Gradient descent on ``½‖e‖²``, ``q ← q + α Jᵀ e``. ``step="armijo"`` (default)
        starts each line search at Buss's step ``α₀ = ⟨e, JJᵀe⟩ / ‖JJᵀe‖²`` (the minimiser
        along ``Jᵀe`` of the linearised error) and backtracks until the Armijo condition
        holds, so ``‖e‖`` never increases; a number is a constant ``α``.
    ``"hybrid"``
        Transpose (Armijo) steps while ``‖e‖ > switch_error`` (default 0.1), where the
        gradient is robust, then Newton steps ``q ← q + J⁺ e`` for quadratic terminal
        convergence; an increasing Newton step falls back to a gradient step.
    ``"dls"`` (default)
        Damped least squares / Levenberg–Marquardt (Wampler 1986; Nakamura & Hanafusa 1986;
        damping after Sugihara 2011):

        .. math:: Δq = J^T (J J^T + λ I)^{-1} e, \qquad λ = μ\,‖e‖^2 + λ_{min},

        with ``(JᵀJ + λI)⁻¹Jᵀe`` when ``n < 6``. A trial is accepted only when it lowers
        ``‖e‖`` (then ``μ`` shrinks), otherwise it is rejected and ``μ`` grows; an attempt
        that stops making progress ends early and a restart takes over, from the nearest
        in pose of ``candidates`` random configurations. The attempts and restarts run in
        the compiled kernel of :mod:`redik.solvers.dls` — the same code as
        :func:`redik.solvers.batch.solve_batch` — on the robot's chain compiled once per frame.
    ``"qp"``
        The task-stack driver :func:`redik.solve_problem` on a one-task
        :class:`redik.Problem` (:func:`redik.solvers.pose.qp.solve_pose_qp`).

Error:
    ``"transpose"``, ``"hybrid"`` and ``"dls"`` drive the world-frame error
    ``e = (p_d − p, log(R_d Rᵀ))`` whose Jacobian is MuJoCo's world Jacobian (``"world"``
    in :mod:`redik.core.conventions`) and whose two halves are exactly the reported position and
    rotation errors; ``"newton"`` drives the body (or space) twist. ``error_history`` holds
    ``‖e‖`` of the method's own error; ``result.error`` is always ``‖log(T⁻¹ T_d)‖``.

Limits
    With ``respect_limits=True`` every iterate stays inside the joint limits and random
    restarts are drawn inside them, so the returned ``q`` is inside the limits. ``"dls"``
    stops a joint that would leave its range at the limit and re-solves for the others
    (a clamping loop); a limited revolute joint whose range spans a full turn is wrapped by
    2π instead; the other methods project (``q ← clip(q + Δq)``). An attempt stuck against
    a limit ends early and a restart takes over. With ``respect_limits=False`` the
    iterations are the textbook ones and the limits are not part of success (the message
    says when ``q`` is outside). In both cases a revolute joint outside its range is
    finally shifted by a multiple of 2π when that brings it inside (the pose is unchanged).

Success
    Decided from the pose of the returned ``q``: ``‖p_d − p‖ ≤ pos_tol``,
    ``angle(Rᵀ R_d) ≤ rot_tol`` and, with ``respect_limits``, ``lower ≤ q ≤ upper``.
    A target farther from the first joint than the chain can reach, or one at which every
    attempt stops at the same non-zero error with a vanishing gradient ``Jᵀe``, is
    ``"unreachable"``; other failures are ``"max_iterations"`` (or ``"diverged"`` when
    every attempt hit a NaN). ``q`` is then the closest configuration found. A failure
    with ``respect_limits`` that is not beyond reach (nor a divergence) is then diagnosed
    by one solve without the limits (same method and seed, at most two restarts): if that
    one converges outside the limits, the status is ``"limits"`` and the message names the
    joints at their limits and those the unconstrained solution puts outside. The extra
    solve is paid on failure only (``diagnose_limits=False`` skips it).
"""

from redik.solvers.pose.options import MAX_ITERATIONS, METHODS, RESTARTS
from redik.solvers.pose.solve import solve_all, solve_pose

__all__ = ["MAX_ITERATIONS", "METHODS", "RESTARTS", "solve_all", "solve_pose"]

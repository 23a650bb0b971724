r"""Conventions used throughout redik — written once here, referred to everywhere else.

Units
    Lengths in metres, angles in radians, time in seconds. A scene file that uses other
    length units says so in its header (none of the bundled scenes do).

Poses
    A pose is a 4×4 homogeneous transform ``T = [[R, p], [0, 1]]`` with ``R ∈ SO(3)``.
    ``T_ab`` maps coordinates expressed in frame *b* to frame *a*: ``x_a = T_ab x_b``.
    ``robot.fk(q, frame)`` returns ``T_wf``: the frame *f* (the end-effector by default) in the
    MuJoCo **world** frame *w*, which is also redik's **space** frame *s*.

Quaternions
    Scalar first, ``(w, x, y, z)``, as in MuJoCo.

Twists and Jacobians
    A twist (spatial velocity) is a 6-vector ordered **linear first**, ``ξ = (v, ω)``, as
    MuJoCo's ``mj_jac*`` (``jacp`` stacked over ``jacr``) and mink's ``SE3`` tangent.
    The only input that uses the other order is ``Robot.from_screws``, whose screw
    axes follow Modern Robotics (``S = (ω, v)``) because that is how they are published.

    ``robot.jacobian(q, frame, reference)`` returns ``J`` (6 × n) with ``ξ = J q̇`` where

    ``reference="world"``
        ``v = ṗ``, the velocity of the frame origin, and ``ω`` the angular velocity,
        both in world coordinates (MuJoCo's ``mj_jacSite``; often called "mixed" or
        "hybrid").
    ``reference="space"``
        The spatial twist ``V_s`` with ``[V_s] = Ṫ T⁻¹`` (Modern Robotics §5.1.1):
        ``ω_s = ω`` and ``v_s = ṗ − ω × p``, the velocity of the body-fixed point that is
        momentarily at the world origin.
    ``reference="body"``
        The body twist ``V_b`` with ``[V_b] = T⁻¹ Ṫ`` (Modern Robotics §5.1.2):
        ``v_b = Rᵀ ṗ``, ``ω_b = Rᵀ ω``, both in the frame's own coordinates.

    The three are related by ``V_s = Ad_T V_b`` with, in (v, ω) order,
    ``Ad_T = [[R, [p] R], [0, R]]``.

Pose error
    The error of a pose ``T`` with respect to a desired ``T_d`` is the body twist
    ``ξ_b = log(T⁻¹ T_d)`` (in ``T``'s frame); the scalar errors reported by every solver
    are ``‖p_d − p‖`` (metres) and the rotation angle of ``Rᵀ R_d`` (radians, by the log,
    accurate at small angles).

Joint vector
    On a chain (a robot with an end-effector: the model's site ``ee``, or ``ee=``), ``q``
    holds the hinge and slide joints on the kinematic chain from the model root to the
    end-effector, in that order (``robot.joint_names``). Every other joint of the MuJoCo
    model is held at its ``home`` keyframe value (or ``qpos0``). A joint without a range has
    limits ``±inf``. A whole-model robot (a model that names no end-effector, or
    ``Robot(model, joints=...)``) moves any set of joints, ball and free joints included:
    ``q`` is then their ``qpos`` entries
    (``robot.nq``: a free joint's position then unit quaternion ``(w, x, y, z)``), while
    ``Δq``, Jacobian columns, limits and task costs live in the tangent space (``robot.dof``,
    MuJoCo's velocity coordinates); ``robot.integrate`` and ``robot.difference`` map between
    them (:mod:`redik.kinematics.robot`).

    A hinge whose range spans a full turn (``upper − lower ≥ 2π``, an unlimited one
    included) is **periodic** (``robot.periodic``, :func:`redik.lie.periodic_coordinates`):
    its angle is taken modulo 2π. Solutions and self-motion samples that differ by whole
    turns of such joints are one, distances wrap their differences to (−π, π], and a solver
    step that carries one out of its range wraps it back in by 2π instead of stopping at the
    limit. Any other hinge is compared as it is: ``q`` and ``q + 2π`` are the same pose but
    not the same configuration when only one of them is within the limits.
"""

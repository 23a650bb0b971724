"""``redik explore SCENE``: sample the self-motion manifold of a pose and draw it.

The pose is ``--pose x y z qw qx qy qz`` (metres, scalar-first unit quaternion, world
frame), or the FK of ``--q-ref q1 … qn``, or by default the FK of the scene's ``home``
keyframe. Writes to ``--out DIR``: ``samples.npz`` (:meth:`SelfMotion.save`),
``summary.json``, ``manifold_component.png`` and one ``manifold_<criterion>.png`` per
criterion (joint pairs), and renders of the arm moving along its self-motion with the
end-effector held still (``frames/*.png``, ``selfmotion.gif``, ``selfmotion.mp4``).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from redik.apps.cli._model import add_model_arguments, load_chain
from redik.apps.progress import progress_bar, wanted
from redik.core.rotation_policy import as_quaternion
from redik.lie import make_pose, matrix_from_quat


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``redik explore`` to the command line."""
    parser = subparsers.add_parser(
        "explore", help="sample the self-motion manifold of a pose: NPZ, JSON and pictures"
    )
    add_model_arguments(parser)
    pose = parser.add_mutually_exclusive_group()
    pose.add_argument(
        "--pose", nargs=7, type=float, metavar=("X", "Y", "Z", "QW", "QX", "QY", "QZ"),
        help="target position (m) and unit quaternion (w, x, y, z) in the world frame",
    )  # fmt: skip
    pose.add_argument("--q-ref", nargs="+", type=float, help="target = FK of these joint values")
    parser.add_argument("--out", default="explore_out", help="output directory")
    parser.add_argument("--spacing", type=float, default=None, help="sample spacing (rad)")
    parser.add_argument("--starts", type=int, default=64, help="random IK starts for seeding")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--frames", type=int, default=60, help="rendered frames (0: none)")
    parser.add_argument("--size", nargs=2, type=int, default=(480, 360), metavar=("W", "H"))
    parser.add_argument("--no-mp4", action="store_true", help="skip the MP4 (GIF only)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Explore the self-motion of the pose and draw it; exit code 1 when nothing was found."""
    from redik.solvers.redundancy import explore_self_motion

    robot = load_chain(args)
    initial = None
    if args.pose is not None:
        quat = as_quaternion(np.array(args.pose[3:]), "--pose quaternion")
        T = make_pose(matrix_from_quat(quat), np.array(args.pose[:3]))
    else:
        q_ref = robot.home if args.q_ref is None else robot.check_q(np.array(args.q_ref), "--q-ref")
        T = robot.fk(q_ref)
        initial = q_ref
    progress = progress_bar(desc="exploring", unit="step", enabled=wanted(args.quiet), leave=False)
    with progress:
        motion = explore_self_motion(
            robot, T, spacing=args.spacing, seed=args.seed, n_starts=args.starts, initial=initial
        )
        status = _draw(robot, motion, Path(args.out), args, progress)
    if status == 0:
        print(f"wrote {args.out}/")
    return status


def _draw(robot, motion, out: Path, args: argparse.Namespace, progress) -> int:
    """Write the samples, summary, plots and renders; 1 when there is nothing to draw.

    ``progress`` advances one step per plot, per rendered frame and per written file.
    """
    from redik.apps.selfmotion_plot import plot_joint_pairs

    out.mkdir(parents=True, exist_ok=True)
    motion.save(out / "samples.npz")
    summary = motion.summary()
    (out / "summary.json").write_text(json.dumps(summary, indent=2))
    if len(motion) == 0:
        progress.close()
        print(f"{robot.name}: {motion.status}: {motion.message}; nothing to draw")
        return 1
    color_by = ["component", *motion.criteria]
    picks = _frame_picks(motion, args.frames)
    files = 2 + (not args.no_mp4) if len(picks) else 0  # PNGs, GIF, MP4
    progress.reset(total=len(color_by) + len(picks) + files)
    progress.write(
        f"{robot.name}: {motion.status}, {len(motion)} samples, dimension {motion.dimension}, "
        f"{motion.n_components} component(s), max errors {summary['max_position_error']:.1e} m / "
        f"{summary['max_rotation_error']:.1e} rad, {motion.elapsed:.2f} s"
    )
    if motion.message:
        progress.write(f"note: {motion.message}")
    progress.set_description("plotting")
    for criterion in color_by:
        plot_joint_pairs(
            motion, criterion, lower=robot.lower, upper=robot.upper,
            path=out / f"manifold_{criterion}.png",
        )  # fmt: skip
        progress.update()
    if len(picks):
        _render(robot, motion, picks, out, args, progress)
    return 0


def _frame_picks(motion, frames: int) -> np.ndarray:
    """Indices of the samples to render: ``frames`` spread along the largest component."""
    if frames <= 0:
        return np.empty(0, dtype=int)
    largest = int(np.argmax(np.bincount(motion.component)))
    path = motion.walk(largest)
    return path[np.unique(np.linspace(0, len(path) - 1, frames).round().astype(int))]


def _render(robot, motion, picks, out: Path, args: argparse.Namespace, progress) -> None:
    """Render the picked samples and write them as PNGs, a GIF and (unless told not) an MP4."""
    from redik.apps.render import render_frames, save_gif, save_mp4, save_pngs

    progress.set_description("rendering")
    start = progress.n
    width, height = args.size
    frames = render_frames(
        robot, motion.samples[picks], width, height, target=motion.T_target,
        on_frame=lambda k, total: progress.update(start + k + 1 - progress.n),
    )  # fmt: skip
    progress.set_description("writing frames")
    save_pngs(out / "frames", frames)
    progress.update()
    progress.set_description("writing GIF")
    save_gif(out / "selfmotion.gif", frames)
    progress.update()
    if not args.no_mp4:
        progress.set_description("writing MP4")
        save_mp4(out / "selfmotion.mp4", frames)
        progress.update()

"""Calling a foreign task or limit (mink's): its exceptions reach the caller as redik errors.

A mink task inside a :class:`redik.Problem` runs mink's code (``compute_error``,
``compute_qp_residual``…), which may raise anything: mink's ``EqualityConstraintTask`` raised
a raw ``ValueError`` on a model whose constraint rows it could not read. Every call into such
an object goes through :func:`foreign_call`, so the caller gets a
:class:`~redik.core.exceptions.TaskError` that names the task and the method, with the
original exception chained.
"""

from __future__ import annotations

from typing import Any

from redik.core.exceptions import RedikError, TaskError


def foreign_call(owner: object, method: str, *args: object) -> Any:
    """``owner.method(*args)``, an exception of another library raised as a :class:`TaskError`.

    A redik error passes through; any other exception (a mink task's ``ValueError``) is
    raised as a :class:`~redik.core.exceptions.TaskError` naming the task or limit and the
    method, with the original chained.

    Args:
        owner: A task or limit (redik's or mink's).
        method: The name of the method to call.
        *args: Its arguments.

    Returns:
        What the method returns.

    Raises:
        TaskError: the method raised an exception that is not a redik error.
    """
    try:
        return getattr(owner, method)(*args)
    except RedikError:
        raise
    except Exception as error:
        raise TaskError(
            f"{describe(owner)} raised {type(error).__name__} in {method}: {error}"
        ) from error


def describe(owner: object) -> str:
    """``"task EqualityConstraintTask (mink)"``, with its frame when it has one."""
    kind = "task" if hasattr(owner, "compute_qp_objective") else "limit"
    frame = getattr(owner, "frame_name", None)
    where = f" on {frame!r}" if isinstance(frame, str) else ""
    return f"{kind} {type(owner).__name__}{where} ({type(owner).__module__.split('.')[0]})"

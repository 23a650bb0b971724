"""The kinematic description a generated model carries in its ``<custom>`` section.

:func:`~redik.models.builder.dh_to_mjcf` stores the DH table and
:func:`~redik.models.builder.screws_to_mjcf` the space screws and ``M``, so that the file alone
says which textbook description it was built from: :func:`read_dh` and :func:`read_screws`
recover them. This module owns the names of those entries and both directions of the format.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np
from numpy.typing import NDArray

from redik.core.exceptions import ModelError
from redik.models.dh import DHRow, parse_convention

# Names of the <custom> entries that carry the kinematic description.
DH_NUMERICS = ("redik_dh_a", "redik_dh_d", "redik_dh_alpha", "redik_dh_theta")
DH_PRISMATIC = "redik_dh_prismatic"
DH_TOOL = "redik_dh_tool"
DH_CONVENTION = "redik_convention"
POE_SCREWS = "redik_poe_screws"
POE_HOME = "redik_poe_M"


def dh_numerics(table: Sequence[DHRow], tool: NDArray[np.float64]) -> dict[str, list[float]]:
    """The ``<numeric>`` entries of a DH table and its 4×4 ``tool`` (row-major)."""
    a, d, alpha, theta = DH_NUMERICS
    return {
        a: [row.a for row in table],
        d: [row.d for row in table],
        alpha: [row.alpha for row in table],
        theta: [row.theta for row in table],
        DH_PRISMATIC: [float(row.is_prismatic) for row in table],
        DH_TOOL: tool.ravel().tolist(),
    }


def dh_texts(convention: str) -> dict[str, str]:
    """The ``<text>`` entries of a DH table: its convention."""
    return {DH_CONVENTION: convention}


def screw_numerics(S: NDArray[np.float64], M: NDArray[np.float64]) -> dict[str, list[float]]:
    """The ``<numeric>`` entries that store space screws ``S`` and the home pose ``M``.

    ``S`` (6 × n) is stored n × 6 row-major, each row ``(ω, v)``; ``M`` row-major.
    """
    return {POE_SCREWS: S.T.ravel().tolist(), POE_HOME: M.ravel().tolist()}


def read_dh(model: mujoco.MjModel) -> tuple[tuple[DHRow, ...], str, NDArray[np.float64]]:
    """Recover ``(rows, convention, tool)`` from a model made by ``dh_to_mjcf``.

    The inverse of :func:`~redik.models.builder.dh_to_mjcf`'s storage.

    Raises:
        ModelError: The model does not carry a DH table.
    """
    try:
        a, d, alpha, theta = (_numeric(model, key) for key in DH_NUMERICS)
        prismatic = _numeric(model, DH_PRISMATIC)
        tool = _numeric(model, DH_TOOL).reshape(4, 4)
        convention = parse_convention(_text(model, DH_CONVENTION))
    except (KeyError, ValueError) as error:
        raise ModelError(
            f"the model carries no DH table (custom numerics "
            f"{', '.join(DH_NUMERICS)}, {DH_PRISMATIC}, {DH_TOOL} and text {DH_CONVENTION}): "
            f"{error}"
        ) from None
    rows = tuple(
        DHRow(a_i, d_i, alpha_i, theta_i, joint="prismatic" if flag else "revolute")
        for a_i, d_i, alpha_i, theta_i, flag in zip(a, d, alpha, theta, prismatic, strict=True)
    )
    return rows, convention, tool


def read_screws(model: mujoco.MjModel) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Recover the space screws ``S`` (6 × n, MR order) and ``M`` of a model.

    The inverse of :func:`~redik.models.builder.screws_to_mjcf`'s storage.

    Raises:
        ModelError: The model does not carry screw axes.
    """
    try:
        S = _numeric(model, POE_SCREWS).reshape(-1, 6).T
        M = _numeric(model, POE_HOME).reshape(4, 4)
    except (KeyError, ValueError) as error:
        raise ModelError(
            f"the model carries no screw axes (custom numerics {POE_SCREWS}, {POE_HOME}): {error}"
        ) from None
    return S, M


def _numeric(model: mujoco.MjModel, key: str) -> NDArray[np.float64]:
    return np.array(model.numeric(key).data, dtype=float)


def _text(model: mujoco.MjModel, key: str) -> str:
    index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_TEXT, key)
    if index < 0:
        raise KeyError(f"no text {key!r}")
    start = int(model.text_adr[index])
    raw = bytes(model.text_data[start : start + int(model.text_size[index])])
    return raw.split(b"\x00", 1)[0].decode()

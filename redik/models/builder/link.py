"""One link of a generated serial arm.

The description both builders produce, and the MJCF text is written from.

:mod:`~redik.models.builder.from_dh` and :mod:`~redik.models.builder.from_screws` describe an
arm as a list of :class:`Link`; :mod:`~redik.models.builder.serial_arm` checks and sizes it and
:mod:`~redik.models.builder.mjcf_text` writes it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray


@dataclass
class Link:
    """One body of the chain, in its parent's coordinates.

    Attributes:
        pose: The body's pose in its parent body at ``q = 0`` (4, 4).
        slide: True for a slide joint, False for a hinge.
        axis: The joint axis, in body coordinates.
        anchor: The joint's position, in body coordinates.
        next_anchor: The next joint's position (or the end-effector's), in body coordinates:
            the link's capsule runs from ``anchor`` to it.
    """

    pose: NDArray[np.float64]
    slide: bool
    axis: NDArray[np.float64]
    anchor: NDArray[np.float64]
    next_anchor: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))

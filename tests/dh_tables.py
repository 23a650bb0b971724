"""The published DH tables of the arms the closed-form tests solve (standard DH)."""

from __future__ import annotations

import numpy as np

from redik.models.dh import DHRow

HALF = np.pi / 2
PUMA560 = (0.4318, 0.01905, 0.1254, 0.4318)
"""``puma_rows``' (a2, a3, d3, d4) of the PUMA 560, in metres."""
UR5E = (0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996)
"""``ur_rows``' (d1, a2, a3, d4, d5, d6) of the UR5e, in metres."""


def puma_rows(a2, a3, d3, d4):
    """The PUMA-type table (Spong, Hutchinson & Vidyasagar §3.3; Craig §3.7 in standard form)."""
    return [
        DHRow(0.0, 0.0, -HALF),
        DHRow(a2, 0.0, 0.0),
        DHRow(a3, d3, HALF),
        DHRow(0.0, d4, -HALF),
        DHRow(0.0, 0.0, HALF),
        DHRow(0.0, 0.0, 0.0),
    ]


def ur_rows(d1, a2, a3, d4, d5, d6):
    """Universal Robots' published table."""
    return [
        DHRow(0.0, d1, HALF),
        DHRow(a2, 0.0, 0.0),
        DHRow(a3, 0.0, 0.0),
        DHRow(0.0, d4, HALF),
        DHRow(0.0, d5, -HALF),
        DHRow(0.0, d6, 0.0),
    ]


def stanford_rows(d2, d6, d1=0.0):
    """The Stanford arm (Spong, Hutchinson & Vidyasagar §3.3.5); row 3 slides, q3 = d3."""
    return [
        DHRow(0.0, d1, -HALF),
        DHRow(0.0, d2, HALF),
        DHRow(0.0, 0.0, 0.0, 0.0, "prismatic"),
        DHRow(0.0, 0.0, -HALF),
        DHRow(0.0, 0.0, HALF),
        DHRow(0.0, d6, 0.0),
    ]

"""redik.apps.plot: convergence curves are drawn from results and saved as PNG."""

from __future__ import annotations

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest

from redik.apps import plot
from redik.core.exceptions import InvalidInput
from redik.solvers.iterative import solve_equations


def square(q: np.ndarray) -> np.ndarray:
    return np.array([q[0] ** 2 + q[1], q[1] ** 3])


def test_convergence_draws_one_curve_per_result_and_saves_a_png(tmp_path):
    results = [
        solve_equations(square, [2.0, 1.0], [1.0, 0.5], tol=1e-12),
        solve_equations(
            square, [2.0, 1.0], [1.0, 0.5], "transpose", step="armijo", max_iterations=50
        ),
    ]
    path = tmp_path / "sub" / "convergence.png"
    ax = plot.convergence(results, ["Newton", "gradient"], path=path)
    assert matplotlib.get_backend().lower() == "agg"
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert ax.get_yscale() == "log"
    lines = ax.get_lines()
    assert [line.get_label() for line in lines] == ["Newton", "gradient"]
    for line, result in zip(lines, results, strict=True):
        # An exact zero cannot sit on a log axis: it is drawn at the smallest positive float.
        expected = np.maximum(result.error_history, np.finfo(float).tiny)
        np.testing.assert_allclose(line.get_ydata(), expected)
        np.testing.assert_array_equal(line.get_xdata(), np.arange(result.error_history.size))
    plt.close(ax.figure)


def test_convergence_draws_on_given_axes_with_default_labels():
    _, ax = plt.subplots()
    result = solve_equations(square, [2.0, 1.0], [1.0, 0.5])
    assert plot.convergence([result], ax=ax) is ax
    assert ax.get_lines()[0].get_label() == "newton"
    plt.close(ax.figure)


def test_convergence_rejects_bad_inputs():
    result = solve_equations(square, [2.0, 1.0], [1.0, 0.5])
    with pytest.raises(InvalidInput):
        plot.convergence([])
    with pytest.raises(InvalidInput):
        plot.convergence([result], ["a", "b"])

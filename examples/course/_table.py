"""The notes' numbers beside redik's, for the course examples (not an example itself).

A number the notes print with ``d`` decimals agrees with redik's value when that value,
rounded to ``d`` decimals, is the printed number — ``"1.7062"`` is matched by every value in
[1.70615, 1.70625), nothing looser. Each cell shows the printed number, redik's value with two
more decimals than the notes print (a count as it is), their difference (redik − notes) and ✓ or ✗.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from redik import RedikError


def decimals(printed: str) -> int:
    """How many decimals the notes print in ``printed`` (``"-0.33284"`` → 5)."""
    return len(printed.split(".")[1]) if "." in printed else 0


def agrees(printed: str, value: float) -> bool:
    """Whether ``value`` rounded to the decimals of ``printed`` is the printed number."""
    return round(float(value), decimals(printed)) == float(printed)


def table(
    title: str,
    columns: Sequence[str],
    rows: Sequence[tuple[str, Sequence[str], Sequence[float]]],
) -> bool:
    """Print ``rows`` of ``(label, the notes' printed values, redik's values)`` side by side.

    Args:
        title: The table's title (the notes' section).
        columns: The name of each value.
        rows: One ``(label, printed, values)`` per row of the notes' table.

    Returns:
        Whether every value agrees at the printed precision.
    """
    print(title)
    head = "".join(
        f"  {name + ' notes':>14} {'redik':>11} {'redik−notes':>11}  " for name in columns
    )
    print(f"  {'':>12}{head}")
    every = True
    for label, printed, values in rows:
        cells = []
        for text, value in zip(printed, values, strict=True):
            ok = agrees(text, value)
            every &= ok
            extra = 0 if isinstance(value, int) else 2  # an iteration count is shown as such
            shown = f"{float(value):.{decimals(text) + extra}f}"
            cells.append(
                f"  {text:>14} {shown:>11} {float(value) - float(text):>+11.1e} {'✓✗'[not ok]}"
            )
        print(f"  {label:>12}" + "".join(cells))
    print(
        f"  → {'every number agrees' if every else 'SOME NUMBERS DIFFER'} at the notes' precision"
    )
    return every


def attempt(label: str, solve: Callable[[], Any]) -> Any:
    """Run ``solve()`` and print its summary; if redik refuses the call, print why.

    Args:
        label: What the run is, as the notes name it.
        solve: A call of redik returning an ``IKResult``.

    Returns:
        The result, or None when redik refused the call (an option this redik does not take).
    """
    try:
        result = solve()
    except RedikError as error:
        print(f"  {label}: redik refuses the call: {type(error).__name__}: {error}")
        return None
    print(f"  {label}: {result.summary()}")
    return result

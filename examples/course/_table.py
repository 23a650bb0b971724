"""The notes' numbers beside redik's, for the course examples (not an example itself).

A number the notes print with ``d`` decimals agrees with redik's value when that value,
rounded to ``d`` decimals, is the printed number — ``"1.7062"`` is matched by every value in
[1.70615, 1.70625), nothing looser. Each cell shows the printed number, redik's value with two
more decimals than the notes print, their difference (redik − notes) and ✓ or ✗.
"""

from __future__ import annotations

from collections.abc import Sequence


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
            shown = f"{float(value):.{decimals(text) + 2}f}"
            cells.append(
                f"  {text:>14} {shown:>11} {float(value) - float(text):>+11.1e} {'✓✗'[not ok]}"
            )
        print(f"  {label:>12}" + "".join(cells))
    print(
        f"  → {'every number agrees' if every else 'SOME NUMBERS DIFFER'} at the notes' precision"
    )
    return every

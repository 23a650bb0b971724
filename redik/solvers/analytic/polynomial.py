r"""Real roots of a polynomial of degree at most 4, compiled and allocation-free.

The quartic is solved by Ferrari's method (Abramowitz & Stegun 1964, 3.8.3): the depressed
quartic :math:`y^4 + p y^2 + q y + r` (:math:`x = y - b/4`) splits into two real quadratics once
the largest root :math:`m > 0` of the resolvent cubic
:math:`m^3 + p m^2 + (p^2/4 - r) m - q^2/8 = 0` is known,

.. math::
    \Bigl(y^2 - \sqrt{2m}\,y + \tfrac{p}{2} + m + \tfrac{q}{2\sqrt{2m}}\Bigr)
    \Bigl(y^2 + \sqrt{2m}\,y + \tfrac{p}{2} + m - \tfrac{q}{2\sqrt{2m}}\Bigr) = 0,

the cubic by Cardano's formula (trigonometric when it has three real roots, A&S 3.8.2), and
each quadratic without cancellation (the larger root first, the other from the product).
Every root is then refined by up to two Newton steps on the original polynomial, each kept
only if it lowers |p|: the closed form loses digits next to a double root, Newton restores
them where the root is simple and cannot jump away from a double one. A
quadratic whose discriminant is negative by less than :data:`DOUBLE` (relative) is taken at
its double root, so that a tangency (two solutions merging) is kept rather than dropped: the
caller's verification decides whether it solves its problem.
"""

from __future__ import annotations

import math

import numba

from redik.kinematics.compiled import COMPILE

#: A quadratic's discriminant within ``−DOUBLE · scale²`` of 0 is a double root.
DOUBLE = 1e-9

#: Leading coefficients below this fraction of the largest coefficient drop the degree.
NEGLIGIBLE = 1e-12


@numba.njit(**COMPILE)
def _quadratic(b, c, out, count):
    """Append the real roots of ``y² + b y + c`` to ``out`` from ``count``; the new count."""
    disc = b * b - 4.0 * c
    if disc < -DOUBLE * max(b * b, abs(c), 1e-300):
        return count
    if disc <= 0.0:
        out[count] = -0.5 * b
        return count + 1
    big = -0.5 * (b + math.copysign(math.sqrt(disc), b))
    out[count] = big
    out[count + 1] = c / big if big != 0.0 else 0.0
    return count + 2


@numba.njit(**COMPILE)
def _largest_cubic_root(a, b, c):
    """The largest real root of ``m³ + a m² + b m + c`` (Cardano), two Newton steps on."""
    q = (a * a - 3.0 * b) / 9.0
    r = (2.0 * a * a * a - 9.0 * a * b + 27.0 * c) / 54.0
    if r * r < q * q * q:
        theta = math.acos(min(max(r / math.sqrt(q * q * q), -1.0), 1.0))
        m = -2.0 * math.sqrt(q) * math.cos((theta + 2.0 * math.pi) / 3.0) - a / 3.0
    else:
        big = -math.copysign((abs(r) + math.sqrt(r * r - q * q * q)) ** (1.0 / 3.0), r)
        m = big + (q / big if big != 0.0 else 0.0) - a / 3.0
    for _ in range(2):
        slope = (3.0 * m + 2.0 * a) * m + b
        if slope == 0.0:
            break
        m -= (((m + a) * m + b) * m + c) / slope
    return m


@numba.njit(**COMPILE)
def _value_and_slope(coefficients, start, x):
    """``(p(x), p'(x))`` of ``coefficients[start:]`` (highest power first), by Horner."""
    value = 0.0
    slope = 0.0
    for k in range(start, 5):
        slope = slope * x + value
        value = value * x + coefficients[k]
    return value, slope


@numba.njit(**COMPILE)
def _newton(coefficients, start, x):
    """Refine a root by guarded Newton steps.

    Two Newton steps on ``coefficients[start:]`` from ``x``, each kept only if it lowers
    ``|p|``: next to a double root p' vanishes and a step could jump to another root.
    """
    value, slope = _value_and_slope(coefficients, start, x)
    for _ in range(2):
        if slope == 0.0 or value == 0.0:
            break
        trial = x - value / slope
        trial_value, trial_slope = _value_and_slope(coefficients, start, trial)
        if not abs(trial_value) < abs(value):
            break
        x, value, slope = trial, trial_value, trial_slope
    return x


@numba.njit(**COMPILE)
def _biquadratic(p, r, shift, out):
    """Roots of ``y⁴ + p y² + r`` (``y² = z``), shifted by ``shift``; how many."""
    # The two values of z go to the end of ``out`` and are read before roots overwrite them.
    found = _quadratic(p, r, out, 2)
    squares = (out[2], out[3])
    found -= 2
    count = 0
    for k in range(found):
        z = squares[k]
        if z >= 0.0:
            w = math.sqrt(z)
            out[count] = w + shift
            out[count + 1] = -w + shift
            count += 2
        elif z > -DOUBLE * max(abs(p), 1.0):
            out[count] = shift
            count += 1
    return count


@numba.njit(**COMPILE)
def _quartic(b, c, d, e, out):
    """Real roots of the monic ``x⁴ + b x³ + c x² + d x + e`` (Ferrari); how many."""
    shift = -0.25 * b
    p = c - 0.375 * b * b
    q = d - 0.5 * b * c + 0.125 * b * b * b
    r = e - 0.25 * b * d + b * b * c / 16.0 - 3.0 * b**4 / 256.0
    if abs(q) <= 1e-14 * max(1.0, abs(p) ** 1.5, abs(r) ** 0.75):
        return _biquadratic(p, r, shift, out)
    m = max(_largest_cubic_root(p, 0.25 * p * p - r, -0.125 * q * q), 1e-300)
    s = math.sqrt(2.0 * m)
    t = q / (2.0 * s)
    count = _quadratic(-s, 0.5 * p + m + t, out, 0)
    count = _quadratic(s, 0.5 * p + m - t, out, count)
    for k in range(count):
        out[k] += shift
    return count


@numba.njit(**COMPILE)
def real_roots(coefficients, out):
    """Real roots of ``c[0] x⁴ + c[1] x³ + … + c[4]`` into ``out`` (≥ 4 entries).

    Args:
        coefficients: The five coefficients, highest power first; leading ones below
            :data:`NEGLIGIBLE` of the largest lower the degree.
        out: Where the roots are written (unordered; a double root once or as a close pair).

    Returns:
        How many roots were written.
    """
    size = 0.0
    for k in range(5):
        size = max(size, abs(coefficients[k]))
    if size == 0.0:
        return 0
    start = 0
    while start < 4 and abs(coefficients[start]) <= NEGLIGIBLE * size:
        start += 1
    lead = coefficients[start]
    degree = 4 - start
    if degree == 1:
        out[0] = -coefficients[4] / lead
        return 1
    if degree == 2:
        count = _quadratic(coefficients[3] / lead, coefficients[4] / lead, out, 0)
    elif degree == 3:
        a, b, c = coefficients[2] / lead, coefficients[3] / lead, coefficients[4] / lead
        out[0] = _largest_cubic_root(a, b, c)
        # m³ + a m² + b m + c = (x − m)(x² + (a + m) x + b + (a + m) m)
        count = _quadratic(a + out[0], b + (a + out[0]) * out[0], out, 1)
    else:
        count = _quartic(
            coefficients[1] / lead, coefficients[2] / lead, coefficients[3] / lead,
            coefficients[4] / lead, out,
        )  # fmt: skip
    for k in range(count):
        out[k] = _newton(coefficients, start, out[k])
    return count


@numba.njit(**COMPILE)
def near_double(coefficients, x, tol):
    r"""Whether a root is a double root.

    Whether ``x`` is, within ``tol`` (relative), a double root of the quartic
    ``coefficients`` (highest power first): :math:`|p'(x)| \le \mathrm{tol} \sum_k k
    |c_k x^{k-1}|`, the derivative against the size of its terms.
    """
    slope = 0.0
    size = 0.0
    power = 1.0  # x^(d − 1) for the term of degree d
    for d in range(1, 5):
        term = d * coefficients[4 - d] * power
        slope += term
        size += abs(term)
        power *= x
    return abs(slope) <= tol * max(size, 1e-300)

"""Both elbow solutions of a planar 2R arm, and what happens at the workspace edges."""

from __future__ import annotations

import numpy as np

from redik.solvers.analytic import planar_2r, planar_2r_batch, planar_3r_family

l1, l2 = 1.0, 0.8
for x, y in [(1.2, 0.5), (l1 + l2, 0.0), (l1 - l2, 0.0), (2.3, 0.0), (0.1, 0.0)]:
    result = planar_2r(x, y, l1, l2)
    print(f"target ({x:.2f}, {y:.2f}): ", end="")
    if not result:
        print(f"no solution — {result.reason}")
        continue
    print(", ".join(f"{q.label} {np.round(np.degrees(q.q), 2)}°" for q in result))
    for q in result:
        if q.singular:
            print(f"    singular: {q.singular}")

same = planar_2r(0.0, 0.0, 1.0, 1.0)
print(f"\nl1 = l2 at the origin: {same[0].singular}; θ1 = 1 gives {same.families[0].at(1.0)}")

limits = (np.array([-np.pi, 0.0]), np.array([np.pi, np.pi]))  # elbow may only bend one way
print(f"with θ2 ≥ 0 only: {planar_2r(1.2, 0.5, l1, l2, limits=limits).labels}")

xy = np.random.default_rng(0).uniform(-2.0, 2.0, (10_000, 2))
batch = planar_2r_batch(xy, l1, l2)
print(f"\n10 000 random targets: {batch.valid.any(axis=1).mean():.1%} reachable")

family = planar_3r_family(1.5, 0.4, l1, l2, 0.3)
print(
    f"3R arm (l3 = 0.3) at (1.5, 0.4): reachable headings φ ∈ {np.round(family.phi_intervals, 3)}"
)

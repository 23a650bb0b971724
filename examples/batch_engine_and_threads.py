"""Own the workers: one process pool for several batches, and one robot shared by threads.

Run: python examples/batch_engine_and_threads.py
"""

from concurrent.futures import ThreadPoolExecutor

import numpy as np

import redik
from redik.solvers.batch import Chain, Engine, forward_kinematics, solve_batch

robot = redik.load("panda")
chain = Chain.from_robot(robot)
rng = np.random.default_rng(0)
batches = [forward_kinematics(chain, robot.random_q(rng, size=300)) for _ in range(3)]

with Engine("process", workers=2) as engine:  # the pool starts on first use...
    for T in batches:
        result = solve_batch(chain, T, seed=0, engine=engine)  # ...and serves every batch
        print(f"{engine}: {result.summary()}")
print(engine)  # closed: its worker processes have exited

# One robot, several threads: the "dls" solver kept in solver_cache(robot) is built once
# and shared; each thread gets the same answer it would get alone.
targets = batches[0][:24]
with ThreadPoolExecutor(4) as pool:
    threaded = list(pool.map(lambda i: redik.solve_pose(robot, targets[i], seed=i), range(24)))
serial = [redik.solve_pose(robot, T, seed=i) for i, T in enumerate(targets)]
same = all(np.array_equal(a.q, b.q) for a, b in zip(threaded, serial, strict=True))
print(f"{sum(r.success for r in threaded)}/24 solved from 4 threads; as in series: {same}")

"""The process and Ray engines give the same results as the local one, chunk for chunk, on
this machine and on a Ray cluster started the way users start one; a worker killed mid-run
changes no result; an Engine owns its pool (kept between calls, stopped on close and at exit).

Every Ray test keeps its traffic on loopback addresses other than ``127.0.0.1`` (which Ray
replaces by the machine's interface address): the head on ``127.0.0.2``, a second node on
``127.0.0.3``, both with token authentication as Ray 2.60 asks of joining nodes.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import redik
from redik.solvers.batch import Chain, forward_kinematics, solve_batch
from redik.solvers.batch.engines import (
    RETRIES,
    Engine,
    close_shared_engines,
    default_workers,
    map_chunks,
    shared_engine,
)

needs_ray = pytest.mark.skipif(importlib.util.find_spec("ray") is None, reason="no ray")


@pytest.fixture(scope="module")
def problem() -> tuple[Chain, np.ndarray]:
    robot = redik.load("panda")
    chain = Chain.from_robot(robot)
    T = forward_kinematics(chain, robot.random_q(21, size=600))
    T[17, 1, 1] = np.nan  # an invalid target travels through every engine the same way
    return chain, T


def _assert_identical(a, b) -> None:
    for field in dataclasses.fields(a):
        np.testing.assert_array_equal(getattr(a, field.name), getattr(b, field.name))


def _square(shared: int, x: int) -> int:
    return shared * x * x


def test_map_chunks_keeps_order_and_reports_progress():
    seen: list[int] = []
    chunks = ((x,) for x in range(9))
    out = map_chunks(_square, 2, chunks, engine="process", workers=2, on_result=seen.append)
    assert out == [2 * x * x for x in range(9)] == seen


@pytest.mark.parametrize("workers", [1, 2])
def test_process_engine_matches_local(problem, workers):
    chain, T = problem
    local = solve_batch(chain, T, seed=5, engine="local", chunk_size=128)
    pooled = solve_batch(chain, T, seed=5, engine="process", workers=workers, chunk_size=128)
    _assert_identical(local, pooled)
    assert local.status_names[17] == "invalid"


def test_missing_ray_says_how_to_install(problem, monkeypatch):
    chain, T = problem
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray now raises ImportError
    with pytest.raises(redik.BackendError, match=r'pip install "redik\[ray\]"'):
        solve_batch(chain, T[:10], engine="ray")


def _pid(shared: float, x: int) -> int:
    time.sleep(shared)  # long enough for every worker to take a chunk
    return os.getpid()


def _die_once(marker_directory: str, x: int) -> int:
    """``x²``; the first attempt at ``x = 3`` kills its own worker."""
    marker = Path(marker_directory) / "died"
    if x == 3 and not marker.exists():
        marker.touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return x * x


def _die_always(marker_directory: str, x: int) -> int:
    """``x``, except at ``x = 3``, whose every attempt kills its worker (and leaves a mark)."""
    if x == 3:
        (Path(marker_directory) / f"attempt-{os.getpid()}").touch()
        os.kill(os.getpid(), signal.SIGKILL)
    return x


def test_a_process_worker_that_dies_loses_no_chunk(tmp_path):
    with Engine("process", workers=2) as engine:
        out = engine.map(_die_once, str(tmp_path), ((x,) for x in range(12)))
    assert (tmp_path / "died").exists()
    assert out == [x * x for x in range(12)]


def test_a_chunk_that_kills_every_worker_ends_the_map_after_its_retries(tmp_path):
    with Engine("process", workers=2, retries=2) as engine:
        with pytest.raises(redik.BackendError, match="died 3 times"):
            engine.map(_die_always, str(tmp_path), ((x,) for x in range(8)))
        assert len(list(tmp_path.glob("attempt-*"))) == 3  # the first attempt and 2 retries
        assert engine.map(_square, 1, [(2,), (3,)]) == [4, 9]  # a new pool serves the next map
    assert Engine("process").retries == RETRIES


def test_a_process_worker_killed_mid_batch_changes_no_result(problem):
    chain, T = problem
    local = solve_batch(chain, T, seed=5, engine="local", chunk_size=50)
    with Engine("process", workers=2) as engine:
        workers = set(engine.map(_pid, 0.2, ((i,) for i in range(4))))
        killed: list[int] = []

        def kill_a_worker(size: int) -> None:
            if not killed:  # after the first chunk: the next ones are in flight
                killed.append(workers.pop())
                os.kill(killed[0], signal.SIGKILL)

        pooled = solve_batch(chain, T, seed=5, engine=engine, chunk_size=50, progress=kill_a_worker)
        assert killed and not _wait_gone(set(killed))
    _assert_identical(local, pooled)


def _wait_gone(pids: set[int], timeout: float = 10.0) -> set[int]:
    """The pids still alive after up to ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    alive = set(pids)
    while alive and time.monotonic() < deadline:
        for pid in list(alive):
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                alive.discard(pid)
            else:  # a child not yet reaped counts as gone once it is a zombie
                with open(f"/proc/{pid}/stat") as stat:
                    if stat.read().split(") ", 1)[1].startswith("Z"):
                        alive.discard(pid)
        time.sleep(0.05)
    return alive


def test_an_engine_keeps_its_pool_between_calls_and_closes_it():
    with Engine("process", workers=2) as engine:
        assert not engine.in_process
        first = set(engine.map(_pid, 0.0, ((i,) for i in range(16))))
        second = set(engine.map(_pid, 0.0, ((i,) for i in range(16))))
        assert os.getpid() not in first
        assert len(first | second) <= 2  # the same two workers served both calls
    assert engine.closed
    assert not _wait_gone(first | second)
    with pytest.raises(redik.InvalidInput, match="closed"):
        engine.map(_pid, 0.0, [(0,)])
    engine.close()  # closing twice is harmless


def test_solve_batch_on_an_engine_object_matches_local(problem):
    chain, T = problem
    local = solve_batch(chain, T, seed=5, engine="local", chunk_size=128)
    with Engine("process", workers=2) as engine:
        pooled = solve_batch(chain, T, seed=5, engine=engine, chunk_size=128)
        again = solve_batch(chain, T, seed=5, engine=engine, chunk_size=200)
        with pytest.raises(redik.InvalidInput, match="belong to the engine"):
            solve_batch(chain, T, engine=engine, workers=2)
    _assert_identical(local, pooled)
    _assert_identical(local, again)
    with pytest.raises(redik.InvalidInput, match="closed"):
        solve_batch(chain, T, engine=engine)


def test_engine_names_share_one_engine_until_closed():
    engine = shared_engine("process", 2)
    assert shared_engine("process", 2) is engine
    assert shared_engine("process", 3) is not engine
    assert shared_engine("local") is shared_engine("local", default_workers())
    close_shared_engines()
    assert engine.closed
    renewed = shared_engine("process", 2)
    assert renewed is not engine and not renewed.closed


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("gpu",), "engine must be one of"),
        (("process", 0), "workers"),
        (("process", True), "workers"),
        (("process", 2.5), "workers"),
        (("local", None, "10.0.0.1:6379"), "address"),
        (("process", 2, None, -1), "retries"),
    ],
)
def test_bad_engine_arguments_are_refused(args, message):
    with pytest.raises(redik.InvalidInput, match=message):
        Engine(*args)


def test_a_shared_pool_stops_when_the_interpreter_exits():
    script = (
        "from redik.solvers.batch.engines import map_chunks\n"
        "import os\n"
        "def pid(shared, x):\n"
        "    return os.getpid()\n"
        "print(*sorted(set(map_chunks(pid, None, [(i,) for i in range(8)], 'process', 2))))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=True
    )
    workers = {int(pid) for pid in done.stdout.split()}
    assert workers and not _wait_gone(workers)


# --------------------------------------------------------------------------------------
# Ray on loopback: an instance in this process, and a cluster started with `ray start`

RAY = Path(sys.executable).with_name("ray")
HEAD_IP, NODE_IP = "127.0.0.2", "127.0.0.3"

DRIVER = """\
import dataclasses, sys
import numpy as np
import ray
import redik
from redik.solvers.batch import Chain, solve_batch

address, targets, out, chunk_size = sys.argv[1:]
with np.load(targets) as data:
    T = data["T"]
chain = Chain.from_robot(redik.load("panda"))
result = solve_batch(
    chain, T, seed=5, engine="ray", address=address, chunk_size=int(chunk_size)
)
np.savez(out, **{f.name: getattr(result, f.name) for f in dataclasses.fields(result)})
print(*sorted(node["NodeManagerAddress"] for node in ray.nodes() if node["Alive"]))
"""
"""A user's script: solve_batch on the cluster at ADDRESS, the results saved to OUT."""


@pytest.fixture(scope="module")
def ray_token(tmp_path_factory) -> str:
    """A token made as users make one, ``ray get-auth-token --generate`` (in a scratch home:
    the user's ``~/.ray/auth_token`` is left alone)."""
    home = tmp_path_factory.mktemp("home")
    made = subprocess.run(
        [str(RAY), "get-auth-token", "--generate"],
        env=dict(os.environ, HOME=str(home)),
        capture_output=True, text=True, timeout=120, check=True,
    )  # fmt: skip
    token = made.stdout.strip()
    assert len(token) == 64 and (home / ".ray" / "auth_token").read_text().strip() == token
    return token


@dataclasses.dataclass
class _Cluster:
    """Two Ray nodes on this machine, each started by `ray start --block` in its own session."""

    address: str
    environment: dict[str, str]  # what every process of the cluster and its drivers needs
    temp_dirs: list[str]
    nodes: list[subprocess.Popen] = dataclasses.field(default_factory=list)

    def processes(self) -> dict[int, str]:
        """pid → command line of every process of the cluster: the `ray start` processes,
        their descendants, and any process that names one of the cluster's temp dirs."""
        parents, commands = {}, {}
        for entry in Path("/proc").iterdir():
            if entry.name.isdigit():
                try:
                    stat = (entry / "stat").read_text()
                    command = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode()
                except OSError:  # gone meanwhile
                    continue
                parents[int(entry.name)] = int(stat.rsplit(") ", 1)[1].split()[1])
                commands[int(entry.name)] = command
        ours = {node.pid for node in self.nodes} | {
            pid for pid, command in commands.items() if any(t in command for t in self.temp_dirs)
        }
        grown = True
        while grown:
            children = {pid for pid, parent in parents.items() if parent in ours} - ours
            ours |= children
            grown = bool(children)
        return {pid: commands[pid] for pid in ours if pid in commands}

    def start_node(self, *arguments: str, log: Path) -> None:
        """`ray start ARGUMENTS --block`, returning once the node is up."""
        temp = tempfile.mkdtemp(prefix="rdk-")  # short: Ray's socket paths must fit 107 bytes
        self.temp_dirs.append(temp)
        with open(log, "wb") as output:
            node = subprocess.Popen(
                [str(RAY), "start", *arguments, "--temp-dir", temp, "--num-cpus", "1",
                 "--disable-usage-stats", "--block"],
                env=self.environment, stdout=output, stderr=subprocess.STDOUT,
                start_new_session=True,
            )  # fmt: skip
        self.nodes.append(node)
        deadline = time.monotonic() + 180
        while "Ray runtime started" not in log.read_text():
            if node.poll() is not None or time.monotonic() > deadline:
                pytest.fail(f"`ray start {' '.join(arguments)}` failed:\n{log.read_text()[-3000:]}")
            time.sleep(0.2)

    def stop(self) -> None:
        """Stop the processes this cluster started, and only those (`ray stop` would stop
        every Ray process of the user on this machine): SIGTERM to each `ray start --block`,
        which stops its node; SIGKILL to whatever is left."""
        for node in reversed(self.nodes):
            if node.poll() is None:
                node.terminate()
        for node in self.nodes:
            try:
                node.wait(60)
            except subprocess.TimeoutExpired:
                pass
        left = _wait_gone(set(self.processes()), timeout=30)
        for pid in left:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        for temp in self.temp_dirs:
            subprocess.run(["rm", "-rf", temp], check=False)


def _free_port(host: str) -> int:
    with socket.socket() as probe:
        probe.bind((host, 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module")
def ray_cluster(ray_token, tmp_path_factory) -> Iterator[_Cluster]:
    """A head on 127.0.0.2 and a node on 127.0.0.3 joined to it, with token authentication,
    started as the README says."""
    port = _free_port(HEAD_IP)
    environment = dict(os.environ, RAY_AUTH_MODE="token", RAY_AUTH_TOKEN=ray_token)
    environment.pop("RAY_ADDRESS", None)
    cluster = _Cluster(f"{HEAD_IP}:{port}", environment, temp_dirs=[])
    logs = tmp_path_factory.mktemp("ray-logs")
    try:
        cluster.start_node(
            "--head", "--node-ip-address", HEAD_IP, "--port", str(port),
            "--include-dashboard", "false", log=logs / "head.log",
        )  # fmt: skip
        cluster.start_node(
            "--address", cluster.address, "--node-ip-address", NODE_IP, log=logs / "node.log"
        )
        yield cluster
    finally:
        cluster.stop()
    assert not _wait_gone(set(cluster.processes()), timeout=1)


def _drive(cluster: _Cluster, T: np.ndarray, chunk_size: int, tmp_path: Path, **environment):
    """Start the driver script on ``T`` (environment: the cluster's, changed by keywords)."""
    targets = tmp_path / "targets.npz"
    np.savez(targets, T=T)
    env = dict(cluster.environment)
    for name, value in environment.items():
        if value is None:
            env.pop(name, None)
        else:
            env[name] = value
    command = [
        sys.executable, "-c", DRIVER, cluster.address, str(targets), str(tmp_path / "out.npz"),
        str(chunk_size),
    ]  # fmt: skip
    return subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def _driven(driver: subprocess.Popen, tmp_path: Path) -> tuple[redik.BatchResult, str]:
    """The driver's result and what it printed, once it has finished."""
    out, err = driver.communicate(timeout=300)
    assert driver.returncode == 0, err.decode()[-3000:]
    with np.load(tmp_path / "out.npz") as data:
        return redik.BatchResult(**{name: data[name] for name in data.files}), out.decode()


@pytest.fixture(scope="module")
def ray_on_loopback(ray_token) -> Iterator[None]:
    """Ray started in this process with 2 CPUs on 127.0.0.2 (stopped afterwards)."""
    import ray

    assert not ray.is_initialized()
    temp = tempfile.mkdtemp(prefix="rdk-")  # short: Ray's socket paths must fit 107 bytes
    with pytest.MonkeyPatch.context() as monkeypatch:
        # With the token in the environment Ray writes none to ~/.ray; ray.init sets
        # RAY_AUTH_MODE itself, and the context removes it afterwards.
        monkeypatch.setenv("RAY_AUTH_TOKEN", ray_token)
        monkeypatch.delenv("RAY_AUTH_MODE", raising=False)
        ray.init(
            _node_ip_address=HEAD_IP, num_cpus=2, include_dashboard=False, log_to_driver=False,
            _temp_dir=temp,
        )  # fmt: skip
        try:
            yield
        finally:
            ray.shutdown()
            subprocess.run(["rm", "-rf", temp], check=False)


@pytest.mark.slow
@needs_ray
def test_ray_engine_on_a_local_instance_matches_local(problem, ray_on_loopback):
    import ray

    chain, T = problem
    local = solve_batch(chain, T, seed=5, engine="local", chunk_size=128)
    remote = solve_batch(chain, T, seed=5, engine="ray", workers=2, chunk_size=128)
    assert [node["NodeManagerAddress"] for node in ray.nodes()] == [HEAD_IP]
    assert ray.cluster_resources().get("CPU") == 2
    _assert_identical(local, remote)


@pytest.mark.slow
@needs_ray
def test_a_ray_chunk_that_kills_every_worker_ends_the_map_after_its_retries(
    ray_on_loopback, tmp_path
):
    def die_at_3(marker_directory: str, x: int) -> int:  # a closure: Ray ships it by value
        if x == 3:
            (Path(marker_directory) / f"attempt-{os.getpid()}").touch()
            os.kill(os.getpid(), signal.SIGKILL)
        return x

    with Engine("ray", retries=1) as engine:
        with pytest.raises(redik.BackendError, match="died on each of its 2 attempts"):
            engine.map(die_at_3, str(tmp_path), ((x,) for x in range(6)))
        assert engine.map(die_at_3, str(tmp_path), [(1,), (2,)]) == [1, 2]
    assert len(list(tmp_path.glob("attempt-*"))) == 2  # the first attempt and one retry


@pytest.mark.slow
@needs_ray
def test_a_ray_cluster_started_with_ray_start_matches_local(problem, ray_cluster, tmp_path):
    chain, T = problem
    local = solve_batch(chain, T, seed=5, engine="local", chunk_size=128)
    remote, printed = _driven(_drive(ray_cluster, T, 128, tmp_path), tmp_path)
    assert printed.split() == [HEAD_IP, NODE_IP]  # both nodes, on loopback
    _assert_identical(local, remote)


@pytest.mark.slow
@needs_ray
def test_a_ray_worker_killed_mid_batch_changes_no_result(ray_cluster, tmp_path):
    robot = redik.load("panda")
    chain = Chain.from_robot(robot)
    T = forward_kinematics(chain, robot.random_q(8, size=2400))
    T[:, :3, 3] += 3.0  # out of reach: every target spends all its restarts (a long chunk)
    driver = _drive(ray_cluster, T, 400, tmp_path)
    local = solve_batch(chain, T, seed=5, engine="local", chunk_size=400)
    killed = None
    deadline = time.monotonic() + 240
    while killed is None and driver.poll() is None and time.monotonic() < deadline:
        for pid, command in ray_cluster.processes().items():
            if command.startswith("ray::_solve_chunk_task"):  # a worker inside a chunk
                os.kill(pid, signal.SIGKILL)
                killed = pid
                break
        time.sleep(0.05)
    remote, _ = _driven(driver, tmp_path)
    assert killed is not None, "no chunk was seen running"
    _assert_identical(local, remote)


@pytest.mark.slow
@needs_ray
def test_a_driver_without_the_token_mode_is_told_what_to_set(problem, ray_cluster, tmp_path):
    _, T = problem
    # Ray's own wait for the cluster, shortened: the refusal is the same.
    driver = _drive(
        ray_cluster,
        T[:10],
        10,
        tmp_path,
        RAY_AUTH_MODE=None,
        RAY_gcs_server_port_wait_time_s="2",
    )
    _, err = driver.communicate(timeout=300)
    assert driver.returncode != 0
    assert "BackendError" in err.decode() and "RAY_AUTH_MODE=token" in err.decode()

"""No process left behind: `run`, `campaign` and `shrink`, ended normally, by Ctrl-C, SIGTERM or
SIGHUP (and a campaign by SIGKILL), leave none of the processes they started running, with an
adapter that ignores SIGTERM, forks a child that ignores it too and double-forks a setsid daemon
(tests/adapters/hostile.py --case stubborn). Nothing prints a traceback."""
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from harness import DEFAULT_MISSION_DIR, ROOT

from tests.support.external import SHORT

pytestmark = pytest.mark.slow

SUTS = '[stub]\ncommand = "{python} {root}/tests/adapters/hostile.py --case stubborn"\ntime_scale = 10.0\n'


@pytest.fixture
def folder(tmp_path):
    for name in ("interface.toml", "properties.toml", "world.toml", "layer.toml"):
        shutil.copy(DEFAULT_MISSION_DIR / name, tmp_path / name)
    (tmp_path / "golden.mission").write_text(SHORT)
    (tmp_path / "suts.toml").write_text(SUTS)
    return tmp_path


def bench(args: list[str], pids: Path) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "harness", *args], cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env={**os.environ, "HOSTILE_PIDS": str(pids)})


def started(pids: Path, bench: subprocess.Popen) -> list[int]:
    """The adapter's pid, its child's and its daemon's, once all three are written."""
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and bench.poll() is None:
        if pids.exists() and len(found := pids.read_text().split()) >= 3:
            return [int(p) for p in found]
        time.sleep(0.05)
    raise AssertionError(f"the adapter did not start: {bench.poll()} {bench.communicate()}")


def running(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def assert_all_ended(pids: list[int], within_s: float = 5.0) -> None:
    deadline = time.monotonic() + within_s
    while any(map(running, pids)) and time.monotonic() < deadline:
        time.sleep(0.1)
    left = [p for p in pids if running(p)]
    for pid in left:  # not to leave them behind the test either
        os.kill(pid, signal.SIGKILL)
    assert not left, f"left running: {left} of adapter, child, daemon {pids}"


def commands(folder: Path) -> dict[str, list[str]]:
    return {"run": ["run", str(folder / "golden.mission"), "--sut", "stub", "--db", str(folder / "r.duckdb")],
            "campaign": ["campaign", "--mission", str(folder), "--sut", "stub", "--mutants", "0", "--jobs", "1",
                         "--db", str(folder / "c.duckdb")],
            "shrink": ["shrink", "1", "--mission", str(folder), "--db", str(folder / "r.duckdb")]}


@pytest.mark.parametrize("how", [None, signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
@pytest.mark.parametrize("command", ["run", "campaign", "shrink"])
def test_nothing_is_left_running(folder, command, how):
    args = commands(folder)
    if command == "shrink":  # a trace to shrink, made by a run
        made = bench(args["run"], folder / "made-pids")
        made.communicate(timeout=120)
        assert_all_ended([int(p) for p in (folder / "made-pids").read_text().split()])
    pids_file = folder / "pids"
    process = bench(args[command], pids_file)
    pids = started(pids_file, process)
    if how is not None:
        process.send_signal(how)
    _, err = process.communicate(timeout=120)
    assert "Traceback" not in err, err
    if how is not None:
        assert process.returncode == 128 + how
        assert f"stopped ({'Ctrl-C' if how == signal.SIGINT else how.name})" in err, err
    assert_all_ended(pids)


def test_a_killed_campaign_leaves_nothing_running_and_its_workers_say_nothing(folder):
    pids_file = folder / "pids"
    process = bench(commands(folder)["campaign"], pids_file)
    pids = started(pids_file, process)
    process.kill()
    _, err = process.communicate(timeout=60)
    assert_all_ended(pids, within_s=15.0)  # the worker learns of its parent's death, and ends them
    assert "Traceback" not in err and "ConnectionResetError" not in err, err


BUSY_LOOP = "while True: pass"
STOP_WITHIN_S = 20.0  # "a few seconds", on a 2-core machine with a busy loop per core beside it


@pytest.mark.parametrize("command", ["run", "campaign"])
def test_ctrl_c_to_the_group_once_or_twice_at_random_instants_stops_a_loaded_bench(folder, command):
    """Issue 48: Ctrl-C on `run` with an adapter did not stop the bench within 30 s on a loaded
    machine. SIGINT to the bench's process group (as a terminal sends it), once or twice 0.1 s
    apart, at a random instant after its adapter started, with busy loops beside it: it exits
    non-zero within STOP_WITHIN_S, says it stopped, and leaves nothing running."""
    import random
    rng = random.Random(48)
    busy = [subprocess.Popen([sys.executable, "-c", BUSY_LOOP]) for _ in range(os.cpu_count() or 2)]
    try:
        for n in range(3):
            pids_file = folder / f"pids-{command}-{n}"
            args = commands(folder)[command]
            process = subprocess.Popen([sys.executable, "-m", "harness", *args], cwd=ROOT, stdout=subprocess.PIPE,
                                       stderr=subprocess.PIPE, text=True, start_new_session=True,
                                       env={**os.environ, "HOSTILE_PIDS": str(pids_file)})
            pids = started(pids_file, process)
            time.sleep(rng.uniform(0.0, 1.5))
            for _ in range(1 + n % 2):
                os.killpg(process.pid, signal.SIGINT)
                time.sleep(0.1)
            began = time.monotonic()
            _, err = process.communicate(timeout=120)
            took = time.monotonic() - began
            assert process.returncode != 0 and "stopped (Ctrl-C)" in err and "Traceback" not in err, err
            assert took < STOP_WITHIN_S, f"{command} took {took:.1f} s to stop"
            assert_all_ended(pids)
            for leftover in folder.glob("*.duckdb*"):
                leftover.unlink()
    finally:
        for loop in busy:
            loop.kill()
            loop.wait()

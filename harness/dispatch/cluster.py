"""Runs of a campaign on a Dask cluster: `campaign --cluster tcp://HOST:PORT` or `local:N`.

The coordinator (the `campaign` process) stays the only writer of the store: it submits the
runs as Dask tasks (a batch of simulated runs each, one run of an external SUT each), gets each
trace back by value and loads it in its own transaction, exactly as with the local pool, so
resume, ids and seeds are the same and a simulated campaign stores the same whatever machine
ran what.

Before submitting anything it checks, each with a message naming what to do: that the
scheduler answers and has workers; that every worker runs this very code (version and a hash
of harness/ and sql/) and holds the same mission files; that a worker whose process dies
mid-run makes the run fail rather than be re-run elsewhere (the scheduler's
`allowed-failures` is 0: the run is recorded `crashed`, with the reason); and, for external
SUTs, that some worker offers the `sut` resource (`dask worker ... --resources sut=K` caps the
SUT instances one machine runs at once). Runs are never retried (`retries=0`). While the
campaign is connected, each worker keeps the adapters that offer `reuse` between its runs, as
a local campaign does (kept.py), and ends them when the campaign disconnects.
"""
from __future__ import annotations

import hashlib
import importlib.metadata
import itertools
import logging
import threading
from collections import deque
from contextlib import ExitStack, contextmanager
from dataclasses import replace
from functools import lru_cache
from pathlib import Path
from typing import Callable

from harness import MISSIONS_DIR, ROOT, SQL_DIR
from harness.errors import UntimelyError
from harness.target.interface import load_interface
from harness.trace import Trace
from harness.sut.external import kept
from harness.dispatch.announcements import Announcements, announcements, failed_batch
from harness.dispatch.description import Setup, Task

PACKAGE = Path(__file__).resolve().parent.parent  # harness/
ALLOWED_FAILURES = "distributed.scheduler.allowed-failures"
CONNECT_TIMEOUT_S = 10
SUT_RESOURCE = "sut"
LOCAL = "local:"  # `local:N`: N worker processes of this machine, started for the campaign
# Simulated runs a Dask task runs one after the other (some 15 ms each): Dask's cost of a task,
# a round trip through the scheduler and CPU in three processes, is then paid once a batch.
RUNS_PER_BATCH = 16
# Workers that die before a batch's first run begins give its runs back, and that may happen again and
# again (a worker's memory limit, a machine lost): this many times, the campaign stops rather than loop.
UNEXPLAINED_DEATHS = 3


def _import_distributed():
    try:
        import distributed
    except ImportError:
        raise UntimelyError("--cluster needs Dask distributed: install the cluster extra, "
                            "`.venv/bin/pip install -e '.[cluster]'`") from None
    return distributed


@lru_cache(maxsize=1)  # once a process: a file edited while it runs does not change the code it loaded
def code_identity() -> dict:
    """What a worker must share with the coordinator: the version and the code itself (named
    alike in a checkout and in an installed wheel, where sql/ and missions/ are in harness/)."""
    digest = hashlib.sha256()
    code = [(f"harness/{p.relative_to(PACKAGE)}", p) for p in PACKAGE.rglob("*.py")
            if not (p.is_relative_to(SQL_DIR) or p.is_relative_to(MISSIONS_DIR))]
    for name, path in sorted(code + [(f"sql/{p.relative_to(SQL_DIR)}", p) for p in SQL_DIR.rglob("*.sql")]):
        digest.update(name.encode() + b"\0" + path.read_bytes())
    return {"version": importlib.metadata.version("untimely"), "code": digest.hexdigest()[:16]}


def _relative(path: Path) -> str:
    """A mission file as workers find it: relative to their own checkout when it is in ours."""
    path = path.resolve()
    return str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else str(path)


def _worker_identity(files: list[str]) -> dict:
    """Runs on each worker: its code identity and the hashes of the mission files it holds."""
    hashes = {}
    for name in files:
        try:
            hashes[name] = hashlib.sha256((ROOT / name).read_bytes()).hexdigest()
        except OSError:
            hashes[name] = None
    return {**code_identity(), "files": hashes}


def _allowed_failures(dask_scheduler) -> int:
    return dask_scheduler.allowed_failures


@lru_cache(maxsize=None)
def _interface(path: str):
    return load_interface(ROOT / path)


_slots_lock, _busy_slots = threading.Lock(), set()


def _run_remote(setup: Setup, task: Task) -> Trace | UntimelyError:
    """Runs on a Dask worker; a slot number per concurrent run of this worker process."""
    with _slots_lock:
        slot = min(set(range(len(_busy_slots) + 1)) - _busy_slots)
        _busy_slots.add(slot)
    try:
        here = replace(setup, world_file=ROOT / setup.world_file)
        return here.run(task, _interface(str(setup.interface_file)), slot)
    finally:
        with _slots_lock:
            _busy_slots.discard(slot)


def _run_batch(setup: Setup, tasks: list[Task], started: Announcements, key: str) -> list[Trace | UntimelyError]:
    """Runs on a Dask worker, one run after the other, each announced before it begins (`key`: the
    batch's task's)."""
    traces = []
    with started.opened(key) as announce:
        for task in tasks:
            announce(task.trace_id)
            traces.append(_run_remote(setup, task))
    return traces


def next_batch(pending: deque, threads: int, external: dict) -> list[Task]:
    """The runs of the next Dask task, taken from the front of `pending`: one run of an external
    SUT (it lasts seconds and holds a `sut` resource), or simulated runs, at most RUNS_PER_BATCH
    and half a fair share of what remains, so that the last batches are short and no thread is
    left with a long one while the others have nothing to run."""
    batch = [pending.popleft()]
    if batch[0].sut not in external:
        size = min(RUNS_PER_BATCH, len(pending) // (2 * threads))
        while len(batch) < size and pending and pending[0].sut not in external:
            batch.append(pending.popleft())
    return batch


_campaigns_lock, _campaigns_kept = threading.Lock(), []  # one ExitStack per connected campaign


def _keep_adapters() -> None:
    """Runs on each worker as a campaign connects: its runs keep reusable adapters from now on."""
    block = ExitStack()
    block.enter_context(kept.kept_adapters())
    with _campaigns_lock:
        _campaigns_kept.append(block)


def _end_kept_adapters() -> None:
    """Runs on each worker as a campaign disconnects; the last one ends the kept adapters."""
    with _campaigns_lock:
        block = _campaigns_kept.pop() if _campaigns_kept else None
    if block is not None:
        block.close()


class Cluster:
    """A connection to a checked Dask cluster; `run_all` has the local pool's contract."""

    def __init__(self, client, setup: Setup, address: str):
        self.client, self.address = client, address
        self.setup = replace(setup, interface_file=Path(_relative(setup.interface_file)),
                             world_file=Path(_relative(setup.world_file)))

    def check(self) -> None:
        distributed = _import_distributed()
        try:
            self.client.wait_for_workers(1, timeout=CONNECT_TIMEOUT_S)
        except (TimeoutError, distributed.TimeoutError):
            raise UntimelyError(f"no Dask worker is connected to {self.address}; start some with "
                                f"`dask worker {self.address}`") from None
        failures = self.client.run_on_scheduler(_allowed_failures)
        if failures != 0:
            raise UntimelyError(f"the scheduler at {self.address} re-runs a task whose worker died "
                                f"({ALLOWED_FAILURES} = {failures}); start it with "
                                "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES=0 so that such a run is "
                                "recorded as crashed, never run twice")
        files = [str(self.setup.interface_file), str(self.setup.world_file)]
        mine = _worker_identity(files)
        for worker, theirs in self.client.run(_worker_identity, files, on_error="return").items():
            if isinstance(theirs, BaseException):
                raise UntimelyError(f"Dask worker {worker} cannot run the bench ({type(theirs).__name__}: "
                                    f"{theirs}); install this project there: `pip install -e '.[cluster]'` "
                                    "in a checkout of the same commit")
            for key in ("version", "code"):
                if theirs[key] != mine[key]:
                    raise UntimelyError(f"Dask worker {worker} runs untimely {key} {theirs[key]}, this bench "
                                        f"{mine[key]}; install the same commit on every worker")
            for name, digest in mine["files"].items():
                if theirs["files"][name] != digest:
                    state = "lacks" if theirs["files"][name] is None else "has another"
                    raise UntimelyError(f"Dask worker {worker} {state} {name}; give every worker the "
                                        "mission files of this campaign")
        if self.setup.external and not any(w.get("resources", {}).get(SUT_RESOURCE)
                                           for w in self.client.scheduler_info()["workers"].values()):
            raise UntimelyError(f"no worker of {self.address} offers the `{SUT_RESOURCE}` resource that runs "
                                f"of external SUTs need; start workers with `dask worker {self.address} "
                                f"--resources {SUT_RESOURCE}=K` (K SUT instances at once on that machine)")

    def run_all(self, tasks: list[Task], on_trace: Callable[[Task, Trace], None]) -> None:
        """One batch in flight per worker thread; a thread that ends one gets its next before
        the coordinator fetches and stores the traces of the last."""
        threads = sum(w["nthreads"] for w in self.client.scheduler_info()["workers"].values())
        with announcements(self.client, local=self.address.startswith(LOCAL)) as started:
            self._run_batches(tasks, on_trace, threads, started)

    def _run_batches(self, tasks: list[Task], on_trace: Callable[[Task, Trace], None], threads: int,
                     started: Announcements) -> None:
        pending, futures, announced, numbers = deque(tasks), {}, set(), itertools.count(1)
        completed, unexplained = _import_distributed().as_completed(), 0

        def submit() -> None:
            batch, key = next_batch(pending, threads, self.setup.external), f"untimely-batch-{next(numbers)}"
            resources = {SUT_RESOURCE: 1} if batch[0].sut in self.setup.external else None
            # the setup goes by value (some 400 bytes): scattered, it would die with the last worker holding it
            future = self.client.submit(_run_batch, self.setup, batch, started, key, pure=False, retries=0, key=key,
                                        resources=resources)
            futures[future] = batch
            completed.add(future)
        try:
            while pending and len(futures) < threads:
                submit()
            for future in completed:
                batch, failed = futures.pop(future), future.status == "error"
                if failed:
                    error = future.exception()
                    announced.update(started.read(future.key, self.client))
                    crashes = failed_batch(batch, error, announced, pending)
                    unexplained += not crashes  # its worker died before it announced a run
                    if unexplained == UNEXPLAINED_DEATHS:
                        raise UntimelyError(f"Dask workers died {unexplained} times before beginning a run of their "
                                            f"batch (the last: {type(error).__name__}: {error}); they cannot run this "
                                            "campaign: see their logs (a memory limit, a killed process), then run "
                                            "the same command again to resume it")
                while pending and len(futures) < threads:
                    submit()
                for task, result in crashes if failed else zip(batch, future.result()):
                    if isinstance(result, UntimelyError):
                        raise result
                    on_trace(task, result)
        finally:
            self.client.cancel(list(futures))


@contextmanager
def connect(address: str, setup: Setup, jobs: int):
    """A checked cluster: `local:N` starts N local worker processes (one thread each for the
    simulator; for external SUTs, threads and `sut` resources to share `jobs` slots), anything
    else is a scheduler address."""
    distributed = _import_distributed()
    cluster = None
    # Dask's profiler samples every worker thread's stack each 10 ms, slowing runs by some 5%
    with __import__("dask").config.set({ALLOWED_FAILURES: 0, "distributed.worker.profile.enabled": False}):
        if address.startswith(LOCAL):
            workers = address.removeprefix(LOCAL)
            if not workers.isdigit() or int(workers) < 1:
                raise UntimelyError(f"--cluster {address!r}: give local:N with N >= 1 workers")
            slots = -(-jobs // int(workers)) if setup.external else 1
            cluster = distributed.LocalCluster(n_workers=int(workers), threads_per_worker=slots, processes=True,
                                               dashboard_address=None, silence_logs=logging.ERROR,
                                               resources={SUT_RESOURCE: slots} if setup.external else None)
            target = cluster
        else:
            target = address
        try:
            client = distributed.Client(target, timeout=f"{CONNECT_TIMEOUT_S}s")
        except (OSError, TimeoutError) as e:
            if cluster:
                cluster.close()
            raise UntimelyError(f"cannot reach the Dask scheduler at {address} ({e}); start it with "
                                "`dask scheduler`, or check the address") from None
    kept_on_workers = False
    try:
        backend = Cluster(client, setup, address)
        backend.check()
        if setup.external:
            client.run(_keep_adapters)
            kept_on_workers = True
        yield backend
    finally:
        if kept_on_workers:
            client.run(_end_kept_adapters, on_error="return")
        client.close()
        if cluster:
            cluster.close()

"""Campaigns on a Dask cluster (`campaign --cluster`): local clusters on loopback, the same store as
the local pool, a worker dying mid-campaign, and the checks made before anything is submitted."""
import time
from collections import deque
from contextlib import ExitStack, contextmanager
from dataclasses import replace

import cloudpickle
import pytest

from harness import DEFAULT_MISSION_DIR, store
from harness.campaign import campaign
from harness.dispatch import announcements, cluster
from harness.dispatch import transport
from harness.dispatch.description import Task
from harness.errors import UntimelyError
from tests.support import campaigns, kept
from tests.support.campaigns import arguments, dump, failing_runner, fake_layer_mission

distributed = pytest.importorskip("distributed")
# Dask workers need not have tests/ on their path: the test runners and the census of child
# processes travel by value.
cloudpickle.register_pickle_by_value(campaigns)
cloudpickle.register_pickle_by_value(kept)


@pytest.mark.slow
def test_a_simulated_campaign_on_two_workers_stores_what_the_local_pool_stores(tmp_path):
    pool, dask = tmp_path / "pool.duckdb", tmp_path / "dask.duckdb"
    options = dict(mission=str(DEFAULT_MISSION_DIR), mutants=8, sut="genom,bip-a", seed=2012)
    campaign.main(arguments(db=pool, **options))
    campaign.main(arguments(db=dask, cluster="local:2", **options))
    assert dump(dask) == dump(pool)


@contextmanager
def scheduler_of_its_own(**workers):
    """A scheduler that outlives the campaign, as a team's cluster does (allowed-failures 0), with
    one worker of `workers` options."""
    import dask
    with dask.config.set({cluster.ALLOWED_FAILURES: 0}), distributed.LocalCluster(
            n_workers=1, processes=True, dashboard_address=None, **workers) as local:
        yield local


@pytest.mark.slow
def test_workers_that_die_again_and_again_before_announcing_a_run_stop_the_campaign(tmp_path, monkeypatch):
    """Rather than give the runs back for ever: here no announcement is ever read."""
    monkeypatch.setattr(announcements.Announcements, "read", lambda *_: [])
    mission, db = fake_layer_mission(tmp_path / "mission"), tmp_path / "c.duckdb"
    with pytest.raises(UntimelyError, match=r"Dask workers died 3 times before beginning a run of their batch "
                                            r"\(the last: .*KilledWorker.*\); they cannot run this campaign: see "
                                            r"their logs .*, then run the same command again to resume it"):
        campaign.main(arguments(mission, db, mutants=4, seed=3, cluster="local:1"), runner=failing_runner)


def queues_left(local, seconds: float = 5.0) -> list[str]:
    """The Dask queues a scheduler still holds once those closing have had `seconds` to go."""
    queues, deadline = local.scheduler.extensions["queues"].queues, time.monotonic() + seconds
    while queues and time.monotonic() < deadline:
        time.sleep(0.05)
    return list(queues)


@pytest.mark.slow
@pytest.mark.parametrize("where", ["local:1", "its own scheduler"])
def test_a_worker_dying_mid_run_records_that_run_crashed_and_the_campaign_completes(tmp_path, where):
    """Its batch announced the run in a file (`local:N`) or on a Dask queue (another scheduler)."""
    mission, db = fake_layer_mission(tmp_path / "mission"), tmp_path / "c.duckdb"
    with ExitStack() as stack:
        own = None if where.startswith(cluster.LOCAL) else stack.enter_context(scheduler_of_its_own(threads_per_worker=1))
        campaign.main(arguments(mission, db, mutants=4, seed=3, cluster=own.scheduler_address if own else where),
                      runner=failing_runner)
        assert not (own and queues_left(own)), "the campaign's queue of announcements outlived it on the scheduler"
    con = store.connect(db, read_only=True)
    rows = con.execute("select script_id, sut, outcome, error from traces order by trace_id").fetchall()
    valid = [r[0] for r in con.execute("select script_id from scripts where valid order by 1").fetchall()]
    assert [r[:2] for r in rows] == [(s, v) for s in valid for v in ("genom", "bip-a")]
    crashed = {(sid, sut): error for sid, sut, outcome, error in rows if outcome == "crashed"}
    assert set(crashed) == {(2, "genom"), (3, "genom")}
    assert "ZeroDivisionError: codel divided by zero" in crashed[(2, "genom")]
    assert crashed[(3, "genom")].startswith("the Dask worker running it failed: KilledWorker")


def runs(*suts: str) -> deque:
    return deque(Task(trace_id=n, script_id=n, sut=sut, seed=n, body="") for n, sut in enumerate(suts))


def test_simulated_runs_go_in_batches_that_shorten_towards_the_end_and_external_ones_alone():
    external = {"toy": object()}
    assert len(cluster.next_batch(runs(*["genom"] * 100), 2, external)) == cluster.RUNS_PER_BATCH
    assert len(cluster.next_batch(runs(*["genom"] * 41), 2, external)) == 10  # 40 behind it, 4 halves of shares
    assert len(cluster.next_batch(runs(*["genom"] * 3), 2, external)) == 1
    mixed = runs(*["genom"] * 5, "toy", *["genom"] * 60)
    assert [t.sut for t in cluster.next_batch(mixed, 1, external)] == ["genom"] * 5  # stops at the external run
    assert [t.sut for t in cluster.next_batch(mixed, 1, external)] == ["toy"]
    assert len(mixed) == 60


def test_a_worker_dying_mid_batch_crashes_the_run_it_was_running_and_gives_back_the_others():
    batch, pending = list(runs("genom", "bip-a", "genom", "bip-a")), runs("later")
    worker = type("WorkerState", (), {"address": "tcp://127.0.0.1:1"})()
    death = distributed.KilledWorker("untimely-batch-1", worker, 0)
    announced = {0, 1, 2, 99}
    [(culprit, trace)] = announcements.failed_batch(batch, death, announced, pending)
    assert culprit is batch[2] and trace.outcome == "crashed"
    assert trace.error.startswith("the Dask worker running it failed: KilledWorker")
    assert list(pending) == [batch[0], batch[1], batch[3], Task(0, 0, "later", 0, "")]  # its traces were lost
    again, pending = [batch[0], batch[1], batch[3]], deque()
    assert announcements.failed_batch(again, death, announced, pending) == []  # a second worker died before it began
    assert list(pending) == again


def test_a_batch_that_fails_otherwise_crashes_every_run_in_it():
    batch, pending = list(runs("genom", "bip-a")), deque()
    failed = announcements.failed_batch(batch, TypeError("cannot unpickle"), {0}, pending)
    assert [task for task, _ in failed] == batch and not pending
    assert {trace.error for _, trace in failed} == {"the Dask worker running it failed: TypeError: cannot unpickle"}


@pytest.mark.slow
def test_an_unreachable_scheduler_is_refused_and_nothing_is_written(tmp_path):
    db = tmp_path / "c.duckdb"
    with pytest.raises(UntimelyError, match=r"cannot reach the Dask scheduler at tcp://127.0.0.1:9 \(.*\); "
                                            r"start it with `dask scheduler`"):
        campaign.main(arguments(DEFAULT_MISSION_DIR, db, cluster="tcp://127.0.0.1:9"))
    assert not db.exists()
    with pytest.raises(UntimelyError, match=r"--cluster 'local:zero': give local:N with N >= 1"):
        campaign.main(arguments(DEFAULT_MISSION_DIR, db, cluster="local:zero"))


@pytest.fixture(scope="module")
def scheduler():
    """A scheduler as a user would start it (allowed-failures left at Dask's default) and one
    worker without resources."""
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as local:
        yield local.scheduler_address


def test_a_scheduler_that_would_rerun_a_dead_workers_run_is_refused(scheduler, tmp_path):
    db = tmp_path / "c.duckdb"
    with pytest.raises(UntimelyError, match=r"re-runs a task whose worker died \(distributed.scheduler."
                                            r"allowed-failures = 3\); start it with DASK_DISTRIBUTED__"):
        campaign.main(arguments(DEFAULT_MISSION_DIR, db, cluster=scheduler))
    assert not db.exists()


def checked(address, setup):
    """Run the pre-submission checks against a scheduler whose allowed-failures is 0."""
    with distributed.Client(address) as client:
        client.run_on_scheduler(lambda dask_scheduler: setattr(dask_scheduler, "allowed_failures", 0))
        cluster.Cluster(client, setup, address).check()


def setup_for(mission=DEFAULT_MISSION_DIR, external=None):
    return transport.setup(None, mission / "interface.toml", mission / "world.toml", 0.0, external or {})


def test_workers_with_other_code_are_refused(scheduler, monkeypatch):
    # Only this process's identity changes: the workers compute theirs with their own module.
    monkeypatch.setattr(cluster, "code_identity", lambda: {"version": "0.1.0", "code": "0123"})
    with pytest.raises(UntimelyError, match=r"Dask worker tcp://\S+ runs untimely code \w+, this bench "
                                            r"0123; install the same commit on every worker"):
        checked(scheduler, setup_for())


def test_workers_with_other_mission_files_are_refused(scheduler, monkeypatch, tmp_path):
    """This bench's checkout is made to look like tmp_path, where the mission differs from the
    workers' (the real checkout)."""
    mission = tmp_path / "missions" / "dala"
    mission.mkdir(parents=True)
    (mission / "interface.toml").write_text((DEFAULT_MISSION_DIR / "interface.toml").read_text() + "\n# edited\n")
    (mission / "world.toml").write_bytes((DEFAULT_MISSION_DIR / "world.toml").read_bytes())
    real = cluster.code_identity()  # of the real checkout, which the workers also run
    monkeypatch.setattr(cluster, "code_identity", lambda: real)
    monkeypatch.setattr(cluster, "ROOT", tmp_path)
    with pytest.raises(UntimelyError, match=r"Dask worker tcp://\S+ has another missions/dala/interface.toml; "
                                            r"give every worker the mission files"):
        checked(scheduler, setup_for(mission))
    (mission / "interface.toml").write_bytes((DEFAULT_MISSION_DIR / "interface.toml").read_bytes())
    (mission / "world.toml").rename(mission / "other-world.toml")
    setup = setup_for(mission)
    with pytest.raises(UntimelyError, match=r"Dask worker tcp://\S+ lacks missions/dala/other-world.toml"):
        checked(scheduler, replace(setup, world_file=mission / "other-world.toml"))


def test_external_suts_need_a_worker_offering_the_sut_resource(scheduler, monkeypatch):
    from harness.target.suts import ExternalSut
    setup = setup_for(external={"toy": ExternalSut("toy", command="adapter")})
    with pytest.raises(UntimelyError, match=r"no worker of tcp://\S+ offers the `sut` resource .* "
                                            r"`dask worker tcp://\S+ --resources sut=K`"):
        checked(scheduler, setup)


@pytest.mark.slow
def test_external_suts_run_on_the_cluster_in_slots_of_their_worker(tmp_path):
    from tests.support.external import FAULTY
    db = tmp_path / "c.duckdb"
    campaign.main(arguments(DEFAULT_MISSION_DIR, db, mutants=3, seed=5, sut=f"f=cmd:{{python}} {FAULTY}",
                            time_scale=20.0, jobs=2, cluster="local:1"))
    con = store.connect(db, read_only=True)
    outcomes = con.execute("select outcome, count(*) from traces group by all").fetchall()
    valid = con.execute("select count(*) from scripts where valid").fetchone()[0]
    assert outcomes == [("completed", valid)]
    infos = {r[0] for r in con.execute("select sut_info from trace_runs").fetchall()}
    assert infos <= {"faulty test adapter on slot 0", "faulty test adapter on slot 1"} and len(infos) == 2


@pytest.mark.slow
def test_a_workers_adapters_that_offer_reuse_serve_run_after_run_and_end_with_the_campaign(tmp_path):
    """On a scheduler that outlives the campaign, as a team's cluster does."""
    from tests.support.external import FAULTY
    with scheduler_of_its_own(threads_per_worker=2, resources={cluster.SUT_RESOURCE: 2}) as local, \
            distributed.Client(local) as client:
        db = tmp_path / "c.duckdb"
        campaign.main(arguments(DEFAULT_MISSION_DIR, db, mutants=3, seed=5, time_scale=20.0, jobs=2,
                                sut=f"f=cmd:{{python}} {FAULTY} --reuse answer", cluster=local.scheduler_address))
        left = client.run(kept.adapters)  # the worker's own child processes
    con = store.connect(db, read_only=True)
    outcomes = con.execute("select outcome, count(*) from traces group by all").fetchall()
    infos = [r[0] for r in con.execute("select sut_info from trace_runs").fetchall()]
    con.close()
    assert [outcome for outcome, _ in outcomes] == ["completed"]
    assert sum(info.endswith(", run 1") for info in infos) <= 2 < len(infos), infos  # one start per slot
    assert list(left.values()) == [set()], "a kept adapter outlived the campaign on its worker"

"""Campaigns on a small fake layer (every request ends `ok` after half a second) and what they store:
the runners, the typed request of `campaign`, and a dump of a store to compare two campaigns by."""
import json
import os
import shutil
import time
from pathlib import Path

from harness import DEFAULT_MISSION_DIR, store
from harness.campaign.request import CampaignRequest
from harness.sut.executive import Runner

MARKER = "UNTIMELY_TEST_MARKER"


class FakeLayer:
    def __init__(self, env, variant, interface, world_file):
        self.env, self.world_events = env, [(0.25, "bump", json.dumps({"variant": variant}))]

    def receive(self, rqst_id, service, args, reply):
        reply(rqst_id, "request", None)
        if not service.endswith(("TrackSpeedStart", "ContinuousShot", "Fuse")):  # until stopped
            self.env.call_at(self.env.now + 0.5, lambda: reply(rqst_id, "final", "ok"))

    def ping(self, answer):
        self.env.call_at(self.env.now + 0.01, answer)


fake_runner = Runner(FakeLayer)


def fake_layer_mission(folder: Path) -> Path:
    """A copy of the default mission in `folder`, with an empty world: the fake layer reads none."""
    shutil.copytree(DEFAULT_MISSION_DIR, folder)
    (folder / "world.toml").write_text("# the fake layer reads no world\n")
    return folder


def failing_runner(script, sut, seed, interface, world_file, max_delay):
    """Script 2 raises on genom, script 3 kills its worker on genom; the rest run normally."""
    if sut == "genom" and script.source == "script 2":
        raise ZeroDivisionError("codel divided by zero")
    if sut == "genom" and script.source == "script 3":
        os._exit(3)
    return fake_runner(script, sut, seed, interface, world_file, max_delay)


def stalling_runner(script, sut, seed, interface, world_file, max_delay):
    """Script 4 signals that it started, then never finishes (the test kills the campaign)."""
    if script.source == "script 4":
        Path(os.environ[MARKER]).touch()
        time.sleep(600)
    return fake_runner(script, sut, seed, interface, world_file, max_delay)


def arguments(mission, db, **changes):
    values = dict(mission=str(mission), mutants=6, sut="genom,bip-a", seed=11, jobs=2, ops_per_mutant=1,
                  strategy="random", shrink=False,
                  time_mutations=False, value_mutations=False, operators=None, max_delay=0.003, time_scale=None,
                  cluster=None, db=str(db))
    values.update(changes)
    return CampaignRequest(**values)


def dump(db) -> dict:
    """Every table of a store, in a canonical order, without wall times and creation dates."""
    con = store.connect(db, read_only=True)
    tables = {
        "campaigns": "select campaign_id, mission, seed, config from campaigns",
        "scripts": "select * from scripts",
        "traces": "select * exclude (wall_s) from traces",
        "events": "select * from events order by trace_id, seq",
        "internal_events": "select * from internal_events order by trace_id, seq",
        "world_events": "select * from world_events order by trace_id, t, kind",
        "reply_codes": "select * from reply_codes order by all",
        "verdicts": "select * from verdicts order by all",
    }
    result = {name: con.execute(query + (" order by 1" if "order" not in query else "")).fetchall()
              for name, query in tables.items()}
    con.close()
    return result

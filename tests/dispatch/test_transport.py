"""One Transport protocol for every kind of SUT: a toy kind, an in-memory echo layer, added by one
entry of harness.dispatch.transport.REGISTRY, runs a campaign on the worker pool and an ad-hoc run;
the built-in kinds stay what --sut names."""
from dataclasses import dataclass
from pathlib import Path

import pytest

from harness import DEFAULT_MISSION_DIR, store
from harness.campaign import campaign
from harness.campaign.request import CampaignRequest
from harness.cli import main
from harness.dispatch import transport
from harness.sut.executive import Runner, run_script
from harness.target.suts import ExternalSut

ECHO_S = 0.05  # virtual seconds the echo layer takes to answer


class EchoLayer:
    """Takes each request at once and answers it `ok` ECHO_S later; always answers a ping."""

    def __init__(self, env, sut, interface, world_file):
        self.env, self.world_events = env, []

    def receive(self, rqst_id, service, args, reply):
        reply(rqst_id, "request", None)
        self.env.call_at(self.env.now + ECHO_S, lambda: reply(rqst_id, "final", "ok"))

    def ping(self, answer):
        answer()


@dataclass(frozen=True)
class Echo:
    name: str

    def run(self, script, seed, interface, slot=0, trace_id=0):
        return Runner(EchoLayer)(script, self.name, seed, interface, Path("no world"), 0.0)


def echo(name, setup):
    """The registry entry: SUTs named echo... are echo layers."""
    return Echo(name) if name.startswith("echo") else None


@pytest.mark.slow
def test_a_toy_transport_added_by_one_registry_entry_runs_a_campaign(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(transport, "REGISTRY", [echo, *transport.REGISTRY])
    db = tmp_path / "echo.duckdb"
    assert campaign.main(CampaignRequest(mutants=4, sut="echo,genom", seed=3, jobs=2, db=str(db))) == 0
    con = store.connect(db, read_only=True)
    runs = dict(con.execute("select sut, count(*) from traces group by sut").fetchall())
    assert runs["echo"] == runs["genom"] >= 2
    echoed = con.execute("""select count(*), count(*) filter (where e.reply = 'ok'), bool_and(t.outcome = 'completed')
                            from events e join traces t using (trace_id) where t.sut = 'echo' and e.kind = 'final'
                         """).fetchone()
    requests = con.execute("select count(*) from events join traces using (trace_id) "
                           "where sut = 'echo' and kind = 'request'").fetchone()[0]
    assert echoed == (requests, requests, True) and requests > 0  # every request answered ok, by the echo
    genom = con.execute("select count(distinct reply) from events join traces using (trace_id) "
                        "where sut = 'genom' and kind = 'final'").fetchone()[0]
    assert genom > 1  # the simulated layer ran the other variant, not the echo
    con.close()
    assert main(["run", str(DEFAULT_MISSION_DIR / "golden.mission"), "--sut", "echo", "--db", str(db)]) == 0
    assert "on echo (seed 0)" in capsys.readouterr().out


def test_the_built_in_kinds_run_the_variants_and_the_external_suts():
    setup = transport.setup(run_script, Path("i.toml"), Path("w.toml"), 0.002, {"toy": ExternalSut("toy", address="h:1")})
    assert setup.transport("toy") == transport.ExternalTransport(ExternalSut("toy", address="h:1"))
    assert setup.transport("genom") == transport.Simulated("genom", run_script, Path("w.toml"), 0.002)
    assert setup.transport("echo").name == "echo" and not isinstance(setup.transport("echo"), Echo)

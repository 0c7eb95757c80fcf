"""Adapters kept between runs (`reuse`, docs/protocol.md "Run after run"): within a campaign an
adapter that offers reuse serves run after run on its slot, on a fresh layer each time; a hung or
crashed run's adapter, one that does not answer bye, or a run outside a campaign is not kept;
the block's end leaves no adapter running."""
import pytest

from harness.sut.external import kept
from harness.target.suts import ExternalSut
from tests.support.external import FAULTY
from tests.support.kept import SIMULATOR, adapters, codes, run


def faulty(fault: str, reuse: str) -> ExternalSut:
    return ExternalSut("faulty", command=f"{{python}} {FAULTY} --fault {fault} --after 1 --reuse {reuse}",
                       time_scale=10.0, probe_timeout_s=1.0, startup_s=10.0)


def test_within_a_campaign_one_adapter_serves_each_slot_on_a_fresh_layer(interface):
    before = adapters()
    with kept.kept_adapters():
        traces = [run(SIMULATOR, interface, slot=slot) for slot in (0, 0, 1, 0)]
        assert len(adapters() - before) == 2  # one per slot, kept while the block runs
    assert adapters() - before == set(), "a kept adapter outlived its campaign"
    assert [t.provenance["sut_info"][-21:] for t in traces] == [
        "run 1 of this adapter", "run 2 of this adapter", "run 1 of this adapter", "run 3 of this adapter"]
    assert {t.outcome for t in traces} == {"completed"}
    assert {tuple(codes(t)) for t in traces} == {("wait_init", "ok")}, [codes(t) for t in traces]


def test_outside_a_campaign_an_adapter_serves_one_run(interface):
    before = adapters()
    traces = [run(SIMULATOR, interface) for _ in range(2)]
    assert [t.provenance["sut_info"][-21:] for t in traces] == ["run 1 of this adapter"] * 2
    assert adapters() - before == set()


@pytest.mark.slow
def test_a_crashed_or_hung_run_ends_its_adapter_and_the_next_run_gets_a_fresh_one(interface):
    with kept.kept_adapters():
        for fault, outcome in (("error", "crashed"), ("silent", "hung")):
            bad = run(faulty(fault, "answer"), interface)
            assert bad.outcome == outcome, bad.error
            assert bad.provenance["sut_info"].endswith("run 1")
        well = [run(faulty("none", "answer"), interface) for _ in range(2)]
    assert [t.provenance["sut_info"][-5:] for t in well] == ["run 1", "run 2"]
    assert {t.outcome for t in well} == {"completed"}


@pytest.mark.slow
def test_an_adapter_that_offers_reuse_but_does_not_answer_bye_is_not_kept(interface):
    with kept.kept_adapters():
        traces = [run(faulty("none", "mute"), interface) for _ in range(2)]
    assert [t.provenance["sut_info"][-5:] for t in traces] == ["run 1", "run 1"]
    assert {t.outcome for t in traces} == {"completed"}

"""Races (issue 36): a kept adapter killed while idle is replaced before its slot's next run,
which is `completed`, never `crashed` for the dead adapter; nothing is left running."""
import os
import signal

import pytest

from harness.sut.external import kept
from tests.support.kept import SIMULATOR, adapters, codes, run

KILLS = 3


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM], ids=["SIGKILL", "SIGTERM"])
def test_a_kept_adapter_killed_while_idle_is_replaced_and_the_next_run_is_ok(interface, sig):
    before = adapters()
    with kept.kept_adapters():
        first = run(SIMULATOR, interface)
        assert first.outcome == "completed", first.error
        for _ in range(KILLS):
            (idle,) = kept._idle.values()
            os.kill(idle.process.pid, sig)  # at once: the next run takes the slot milliseconds later
            after = run(SIMULATOR, interface)
            assert after.outcome == "completed", after.error
            assert codes(after) == ["wait_init", "ok"], codes(after)
            assert after.provenance["sut_info"].endswith("run 1 of this adapter"), "a fresh adapter served it"
        assert len(adapters() - before) == 1, "the dead adapters' replacements pile up"
    assert adapters() - before == set(), "an adapter outlived its campaign"

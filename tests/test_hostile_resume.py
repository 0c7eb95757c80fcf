"""Corruption on resume (issue 36): a focused campaign on an external SUT, stopped by SIGTERM or by
two SIGINTs at random instants while its background shrinks run, leaves a store that resumes, and
the resumed campaign ends with the findings and test-trace verdicts of an uninterrupted one.

UNTIMELY_RESUME_KILLS sets how many kills (default 3, about 30 s each on a loaded 2-core
machine; issue 36 asks for 20, run by hand: UNTIMELY_RESUME_KILLS=20). The SUT is a standard-library
adapter that answers every request `ok` at once and the properties are the precondition ones (PEX,
PRE): its verdicts do not depend on the machine's timing, so two campaigns can be compared."""
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time

import pytest

from harness import DEFAULT_MISSION_DIR, store
from tests.test_shrink_external import ADAPTER

KILLS = int(os.environ.get("UNTIMELY_RESUME_KILLS", "3"))
CAMPAIGN_S = 300  # the longest one campaign may take on a loaded machine
ARGS = ["--strategy", "focused", "--sut", "yes-man", "--mutants", "12", "--shrink", "--jobs", "2", "--seed", "5"]


@pytest.fixture(scope="module")
def target(tmp_path_factory):
    folder = tmp_path_factory.mktemp("resume") / "target"
    folder.mkdir()
    for name in ("interface.toml", "golden.mission", "world.toml", "layer.toml"):
        shutil.copy(DEFAULT_MISSION_DIR / name, folder / name)
    header, *entries = (DEFAULT_MISSION_DIR / "properties.toml").read_text().split("[[property]]")
    (folder / "properties.toml").write_text(header + "".join(
        "[[property]]" + e for e in entries if re.search(r'^family = "(PEX|PRE)"$', e, re.M)))
    (folder / "adapter.py").write_text(ADAPTER)
    (folder / "suts.toml").write_text('[yes-man]\ncommand = "{python} adapter.py"\ntime_scale = 50.0\n')
    return folder


def campaign(target, db) -> list[str]:
    return [sys.executable, "-m", "harness", "campaign", "--mission", str(target), *ARGS, "--db", str(db)]


def outcome(db) -> tuple[list, list]:
    """The findings (without trace and script ids, which shrink runs shift) and every test trace's
    verdicts, by test number (the golden is -1) and variant. Not by script text: a test's waits are
    timed from the golden run, a real-time run that differs a little from one campaign to the next."""
    con = store.connect(db, read_only=True)
    try:
        findings = con.execute("select sut, property_id, kind, reproducer_steps from findings order by all").fetchall()
        verdicts = con.execute("""select coalesce((s.mutations->0->>'test')::integer, -1), t.sut, v.property_id,
                                         v.verdict, count(*)
                                  from verdicts v join traces t using (trace_id) join scripts s using (script_id)
                                  where s.kind in ('golden', 'mutant') group by all order by all""").fetchall()
        return findings, verdicts
    finally:
        con.close()


@pytest.fixture(scope="module")
def uninterrupted(target, tmp_path_factory):
    db = tmp_path_factory.mktemp("whole") / "whole.duckdb"
    done = subprocess.run(campaign(target, db), capture_output=True, text=True, timeout=CAMPAIGN_S)
    assert done.returncode == 0, done.stderr[-2000:]
    found = outcome(db)
    assert found[0] and found[1], "the campaign finds and shrinks something: there is something to interrupt"
    return found


def kill(argv: list[str], delay: float, twice: bool) -> tuple[int, str]:
    """Start the campaign, wait for its first finding (its first shrink starts), then `delay` more
    seconds, and stop it: SIGINT twice, or SIGTERM. Its exit status and output."""
    process = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               env={**os.environ, "PYTHONUNBUFFERED": "1"})
    out, deadline = [], time.monotonic() + CAMPAIGN_S
    try:
        for line in process.stdout:
            out.append(line)
            if line.startswith("found") or time.monotonic() > deadline:
                break
        time.sleep(delay)
        for sig in (signal.SIGINT, signal.SIGINT) if twice else (signal.SIGTERM,):
            process.send_signal(sig)
            time.sleep(0.1)
        out.append(process.communicate(timeout=60)[0])
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    return process.returncode, "".join(out)


def test_a_focused_campaign_killed_during_its_shrinks_resumes_to_the_uninterrupted_outcome(target, uninterrupted,
                                                                                           tmp_path):
    rng, interrupted_shrinks = random.Random(36), 0
    for n in range(KILLS):
        db = tmp_path / f"killed-{n}.duckdb"
        code, said = kill(campaign(target, db), rng.uniform(0.0, 6.0), twice=n % 2 == 1)
        assert "Traceback" not in said, said[-3000:]
        con = store.connect(db, read_only=True)
        interrupted_shrinks += con.execute("select count(*) from campaigns "
                                           "where config->>'interrupted' = 'true'").fetchone()[0]
        con.close()
        resumed = subprocess.run(campaign(target, db), capture_output=True, text=True, timeout=CAMPAIGN_S)
        assert resumed.returncode == 0 and "Traceback" not in resumed.stderr, (n, code, resumed.stderr[-3000:])
        findings, verdicts = outcome(db)
        assert findings == uninterrupted[0], f"kill {n} (exit status {code}) resumed to other findings"
        assert verdicts == uninterrupted[1], (f"kill {n} (exit status {code}): other test-trace verdicts", [
            (row[1:], row in verdicts) for row in set(verdicts) ^ set(uninterrupted[1])])
    print(f"{KILLS} kills, {interrupted_shrinks} shrinks interrupted, every resume completed as uninterrupted")

"""Every hostile case ends in a clear message (exit 2, quoting the file or flag and the value) or
in the right outcome: never a traceback, never silence, never a changed store (issues 19 and 36)."""
import pytest

from harness.cli import main
import commands_corpus
from corpus import CASES as ISSUE_19, Place

CASES = ISSUE_19 + commands_corpus.CASES


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_a_hostile_input_ends_in_a_clear_message_or_the_right_outcome(case, tmp_path, capsys):
    place = Place(tmp_path, main)
    if case.prepare:
        case.prepare(place)
        capsys.readouterr()
    code = main(case.argv(place))
    out, err = capsys.readouterr()
    assert "Traceback" not in err + out
    assert code == case.code, err
    if case.code == 2:
        assert err.startswith(("error: ", "usage: ")) and len(err) < 2_000, err
        assert case.expect in err, err
    else:
        assert case.expect in out, out
    if case.check:
        case.check(place)

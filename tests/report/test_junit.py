"""`analyze --junit FILE` and `--fail-on`: JUnit XML that validates against the schema CI servers
read (tests/junit/junit.xsd), a test case per variant and property, failures with their explanation
and reproducer, and the exit status as a merge gate."""
import xml.etree.ElementTree as ET

import pytest
import xmlschema

from harness import store
from harness.cli import main
from tests.support.paths import JUNIT

SCHEMA = xmlschema.XMLSchema(JUNIT / "junit.xsd")


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """bip-a hangs (once, with this seed), bare gives FN and never FP."""
    db = tmp_path_factory.mktemp("junit") / "c.duckdb"
    assert main(["campaign", "--mutants", "30", "--sut", "genom,bip-a,bare",
                 "--db", str(db), "--jobs", "2"]) == 0
    return db


def _count(db, sql):
    con = store.connect(db, read_only=True)
    try:
        return con.execute(sql).fetchall()
    finally:
        con.close()


@pytest.mark.slow
def test_the_junit_file_validates_and_has_a_case_per_variant_and_property(campaign, tmp_path, capsys):
    out = tmp_path / "ci" / "junit.xml"
    assert main(["analyze", "--db", str(campaign), "--junit", str(out)]) == 0
    SCHEMA.validate(str(out))
    root = ET.parse(out).getroot()
    properties = [p for p, in _count(campaign, "select property_id from properties order by position")]
    assert [s.get("name") for s in root] == ["genom", "bip-a", "bare"]
    for suite in root:
        names = [c.get("name") for c in suite.findall("testcase")]
        assert names == ["outcome", *properties]
        assert int(suite.get("tests")) == len(names)
        assert int(suite.get("failures")) == len(suite.findall("testcase/failure"))
    by_name = {(c.get("classname"), c.get("name")): c for c in root.iter("testcase")}
    fn, fp = _count(campaign, "select count(*) filter (where verdict = 'FN'), count(*) filter (where verdict = 'FP') "
                              "from verdicts join traces using (trace_id) where sut = 'bare'")[0]
    assert fn > 0 and fp == 0, "bare protects nothing: FN, never FP"
    failed_pre = [c for (sut, name), c in by_name.items() if sut == "bare" and name.startswith("PRE(")
                  and c.find("failure") is not None]
    assert failed_pre and all(c.find("failure").get("type") == "FN" for c in failed_pre)
    text = failed_pre[0].find("failure").text
    assert "FN" in text and "C is false" in text, "the explain text of the verdict"
    hang = by_name[("bip-a", "outcome")].find("failure")
    assert hang is not None and hang.get("type") == "hung" and "hung" in hang.text
    assert by_name[("bare", "outcome")].find("failure") is None
    assert int(root.get("failures")) == sum(int(s.get("failures")) for s in root)


@pytest.mark.slow
def test_a_shrunk_reproducer_is_quoted_in_its_failure(campaign, tmp_path):
    trace, prop = _count(campaign, "select representative, property_id from bad_behaviours "
                                   "where sut = 'bare' and verdict = 'FN' and property_id like 'PRE(%' "
                                   "order by traces desc, property_id limit 1")[0]
    assert main(["shrink", str(trace), "--property", prop, "--db", str(campaign), "--out", str(tmp_path)]) == 0
    out = tmp_path / "junit.xml"
    assert main(["analyze", "--db", str(campaign), "--junit", str(out)]) == 0
    case = next(c for c in ET.parse(out).getroot().iter("testcase")
                if c.get("classname") == "bare" and c.get("name") == prop)
    assert "Reproducer (shrunk script" in case.find("failure").text
    assert "send " in case.find("failure").text.split("Reproducer")[1]


@pytest.mark.slow
def test_fail_on_sets_the_exit_status(campaign, capsys):
    assert main(["analyze", "--db", str(campaign), "--fail-on", "hung"]) == 1
    assert "--fail-on hung:" in capsys.readouterr().out
    assert main(["analyze", "--db", str(campaign), "--fail-on", "crashed"]) == 0, "nothing crashed"
    assert main(["analyze", "--db", str(campaign), "--fail-on", "FN, fp"]) == 1


@pytest.mark.slow
def test_an_unknown_fail_on_kind_is_refused_naming_it(campaign, capsys):
    assert main(["analyze", "--db", str(campaign), "--fail-on", "fn,slow"]) == 2
    err = capsys.readouterr().err
    assert "--fail-on 'fn,slow': 'slow' is not a kind of bad behaviour" in err and "fn, fp, hung, crashed" in err


@pytest.mark.slow
def test_a_failure_that_is_only_possible_says_so(campaign, tmp_path):
    """A test case whose every failing verdict has alternatives (another order of the events closer
    than epsilon would pass it) says it is only possible; one with certain failures does not."""
    out = tmp_path / "junit.xml"
    assert main(["analyze", "--db", str(campaign), "--junit", str(out)]) == 0
    counts = {(sut, p): (n, possible) for sut, p, n, possible in _count(campaign, """
        select t.sut, v.property_id, count(*), count(*) filter (where not v.certain)
        from verdicts v join trace_scope t using (trace_id)
        where t.counted and v.verdict in ('FN', 'FP') group by all""")}
    failures = {(c.get("classname"), c.get("name")): c.find("failure").get("message")
                for c in ET.parse(out).getroot().iter("testcase") if c.find("failure") is not None}
    kinds = set()
    for key, (n, possible) in counts.items():
        message = failures[key]
        if possible == n:
            kinds.add("all")
            assert message.endswith("each only possible: another order of events closer than epsilon would pass it")
        elif possible:
            kinds.add("some")
            assert f", {possible} of them only possible" in message
        else:
            kinds.add("none")
            assert "possible" not in message
    assert "none" in kinds and kinds & {"all", "some"}, "the campaign has failures for sure and only possible"

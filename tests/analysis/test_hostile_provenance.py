"""Unclear (issue 36): a store analysed by one installation (CI's wheel) and reported by another (a
laptop's checkout) lists no template as changed when no content changed; a template that did change
is named as under the package's sql/, not by the analysing machine's absolute path."""
import shutil

from harness import DEFAULT_MISSION_DIR
from harness.analysis.analyzer import materialise
from harness.analysis.provenance import stale_files, templates
from tests.support.traces import HERE, INTERFACE, load, judged_store

ELSEWHERE = "/opt/ci/venv/lib/python3.11/site-packages/harness/sql/"


def _analysed_elsewhere(tmp_path):
    """A store judged here, its templates recorded as another installation's."""
    mission = tmp_path / "mission"
    mission.mkdir()
    for name in ("properties.toml", "interface.toml"):
        shutil.copy(DEFAULT_MISSION_DIR / name, mission / name)
    fixture = load(HERE / "tables.trace")
    con = judged_store(fixture, 0.01)
    materialise(con, fixture.properties, 0.01, INTERFACE, mission / "properties.toml")
    con.execute("update analysis_files set path = ? || regexp_extract(path, '(oracles|views)/[^/]+$') "
                "where role = 'template'", [ELSEWHERE])
    return con


def test_templates_of_another_installation_with_the_same_contents_are_not_stale(tmp_path):
    con = _analysed_elsewhere(tmp_path)
    assert con.execute("select count(*) from analysis_files where role = 'template' and path like ?",
                       [ELSEWHERE + "%"]).fetchone()[0] == len(templates()), "the store names the other installation's files"
    assert stale_files(con) == []


def test_a_template_whose_contents_changed_is_named_under_sql(tmp_path):
    con = _analysed_elsewhere(tmp_path)
    con.execute("update analysis_files set sha256 = 'other' where path = ?", [ELSEWHERE + "oracles/pc.sql"])
    con.execute("delete from analysis_files where path = ?", [ELSEWHERE + "views/verdicts.sql"])
    assert stale_files(con) == [("template", "sql/oracles/pc.sql"), ("template", "sql/views/verdicts.sql")]

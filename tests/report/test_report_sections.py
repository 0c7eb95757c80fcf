"""The report's sections are data (harness/report/sections.toml, issue 20): the index's links, its
sections and its CSV files are made from the registry's entries, a section is added by an entry
alone (no code, no template), and one reading a relation the store lacks is left out."""
from __future__ import annotations

import re

import pytest

from harness.errors import UntimelyError
from harness.report import sections
from tests.support.report import Page, analysed_store, write_report

BEHAVIOURS = '''
[[section]]
id = "behaviours"
nav = "Bad behaviours"
heading = "Bad behaviours per variant"
note = "Each (variant, verdict, property) that went wrong, with a representative trace."
reads = ["bad_behaviours"]
tables = ["bad_behaviours"]
csv = ["bad_behaviours"]
'''


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    return analysed_store(tmp_path_factory.mktemp("sections") / "campaign.duckdb")


def _index(out) -> str:
    return (out / "index.html").read_text()


def _links(index: str) -> list[str]:
    return re.findall(r'<a href="#(\w+)">', re.search(r"<nav>(.*?)</nav>", index, re.S)[1])


def _headings(index: str) -> list[str]:
    return re.findall(r'<h2 id="(\w+)">', index)


def _with_entry(tmp_path, monkeypatch, entry: str) -> None:
    registry = tmp_path / "sections.toml"
    registry.write_text(sections.REGISTRY.read_text() + entry)
    monkeypatch.setattr(sections, "REGISTRY", registry)


@pytest.mark.slow
def test_links_sections_and_csv_files_are_the_registry_s(store, tmp_path):
    index = _index(write_report(store, tmp_path / "out"))
    ids = [s.id for s in sections.registry()]
    assert _links(index) == _headings(index) == ids
    written = {p.stem for p in (tmp_path / "out").glob("*.csv")}
    assert len(written) == sum(len(s.csv) for s in sections.registry())
    assert re.findall(r'<a href="(\w+)\.csv">', index) and set(re.findall(r'<a href="(\w+)\.csv">', index)) == written


def test_a_section_is_added_by_an_entry_alone(store, tmp_path, monkeypatch):
    _with_entry(tmp_path, monkeypatch, BEHAVIOURS)
    out = write_report(store, tmp_path / "out")
    index = _index(out)
    assert _links(index)[-1] == _headings(index)[-1] == "behaviours"
    assert "<h2 id=\"behaviours\">Bad behaviours per variant</h2>" in index
    assert "Each (variant, verdict, property) that went wrong, with a representative trace." in index
    shown = Page(index).texts("bad_behaviours")
    assert len(shown) > 1 and (out / "bad_behaviours.csv").read_text().count("\n") == len(shown)  # its header and rows


def test_a_section_reading_a_relation_the_store_lacks_is_left_out(store, tmp_path, monkeypatch):
    _with_entry(tmp_path, monkeypatch, BEHAVIOURS.replace('reads = ["bad_behaviours"]', 'reads = ["no_such_view"]'))
    index = _index(write_report(store, tmp_path / "out"))
    assert "behaviours" not in _links(index) + _headings(index)
    assert not (tmp_path / "out" / "bad_behaviours.csv").exists()


def test_a_section_entry_with_an_unknown_key_is_refused_with_the_file(tmp_path, monkeypatch):
    _with_entry(tmp_path, monkeypatch, BEHAVIOURS.replace("heading =", "headng ="))
    with pytest.raises(UntimelyError, match=r"sections.toml: section 'behaviours' has keys .*'headng'"):
        sections.registry()

"""The figures docs/campaign.md quotes for the default campaign are what the bench gives."""
import re
from collections import Counter

from harness import DEFAULT_MISSION_DIR, ROOT
from harness.mutator.operators import generate
from harness.target.script import load_script

DOC = (ROOT / "docs" / "campaign.md").read_text()


def test_the_default_mutants_are_as_docs_campaign_says(interface):
    golden = load_script(DEFAULT_MISSION_DIR / "golden.mission", interface)
    mutants = generate(golden, interface, 300, 2012)
    invalid = sum(not m.valid for m in mutants)
    ops = Counter(m.operations[0]["op"] for m in mutants)
    distinct = len({m.body for m in mutants} | {golden.renumbered().render()})
    assert (f"scripts   301: golden + 300 mutants, {300 - invalid} valid, {invalid} invalid (stored, not run), "
            f"{distinct} distinct bodies") in DOC
    assert f"With the default\narguments {invalid} of 300 are invalid" in DOC
    assert (f"with the defaults, {ops['insert_request']} mutants insert, {ops['swap_requests']} swap and "
            f"{ops['delete_request']} delete") in DOC


def test_the_simulated_seconds_quoted_add_up():
    per_variant = [int(n.replace(",", "")) for n in re.findall(r"crashed; ([\d,]+) simulated s", DOC)]
    total = int(re.search(r"runs/s\), ([\d,]+) simulated s", DOC).group(1).replace(",", ""))
    assert len(per_variant) == 3 and sum(per_variant) == total


def test_readme_and_the_analyzer_doc_quote_the_same_10_million_event_figures():
    """Issue 19: the README said 23 s where docs/analyzer.md said 12.7 s for the same store."""
    readme, analyzer = (ROOT / "README.md").read_text(), (ROOT / "docs" / "analyzer.md").read_text()
    row = next(line for line in readme.splitlines() if "analysis of a synthetic store" in line)
    figures = re.findall(r"DuckDB on \d+ threads? [\d.,]+ s", row)  # as bench/readme_table.py writes it
    assert len(figures) == 2 and all(f in analyzer for f in figures), figures


def test_the_docs_count_the_manipulators_properties():
    count = (ROOT / "missions" / "manipulator" / "properties.toml").read_text().count("[[property]]")
    assert f"Its {count} properties use" in (ROOT / "docs" / "targets.md").read_text()

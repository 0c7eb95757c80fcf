"""`analyze --junit FILE [--fail-on fn,fp,hung,crashed]`: the verdicts as a CI server reads them.

A <testsuite> per variant; in it a <testcase> per property (classname the variant, name the
property id), failed by the FN and FP verdicts of the traces Tables II-IV count, and a
<testcase> "outcome" failed by the hung and crashed traces. A failure's text gives, for the
first few bad verdicts, the `explain` text, and the reproducer shrunk from that behaviour when
there is one. The XML follows the JUnit schema of Ant and Jenkins (tests/junit/junit.xsd), which
GitHub Actions reporters, GitLab and Jenkins read. `--fail-on` makes the command's exit status 1
when a counted trace shows one of the named kinds of bad behaviour, to gate a merge.
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import defaultdict
from pathlib import Path

from harness.analysis.explain import explanations
from harness.errors import UntimelyError
from harness.files import make_folder
from harness.store.database import connect
from harness.store.report_reads import bad_trace_sums
from harness.store.sql import render_query

# --fail-on's kinds, each with the Table II column that counts its traces.
FAIL_ON = {"fn": "with_fn", "fp": "with_fp", "hung": "hung", "crashed": "crashed"}
EXPLAINED = 5  # bad verdicts explained per test case; the others are listed by trace


def fail_on_kinds(option: str) -> list[str]:
    kinds = [k.strip().lower() for k in option.split(",") if k.strip()]
    unknown = [k for k in kinds if k not in FAIL_ON]
    if option.strip() and not kinds:  # `--fail-on ,` would silently turn the gate off
        raise UntimelyError(f"--fail-on {option!r} names no kind of bad behaviour; give a comma-separated list "
                            f"among {', '.join(FAIL_ON)}, or leave the option out for no gate")
    if unknown:
        raise UntimelyError(f"--fail-on {option!r}: {', '.join(map(repr, unknown))} is not a kind of bad "
                            f"behaviour; give a comma-separated list among {', '.join(FAIL_ON)}")
    return kinds


def _failure_text(con, rows: list[dict]) -> str:
    verdicts = [r for r in rows if r["rqst_id"] is not None][:EXPLAINED]
    texts = explanations(con, verdicts)
    parts = []
    for r in rows[:EXPLAINED]:
        if r["rqst_id"] is None:
            parts.append(f"trace {r['trace_id']} {r['failure']}" + (f": {r['error']}" if r["error"] else ""))
        else:
            key = (r["trace_id"], r["property_id"], r["rqst_id"])
            parts.append(texts.get(key, f"trace {r['trace_id']} request {r['rqst_id']}: {r['failure']}"))
    if len(rows) > EXPLAINED:
        parts.append(f"... and {len(rows) - EXPLAINED} more: "
                     + ", ".join(str(r["trace_id"]) for r in rows[EXPLAINED:]))
    shrunk = next((r for r in rows if r["reproducer"] is not None), None)
    if shrunk:
        parts.append(f"Reproducer (shrunk script {shrunk['reproducer']}):\n{shrunk['body']}")
    return "\n\n".join(parts)


def _possible(possible: int, failures: int) -> str:
    """What a message adds when some failures are only possible: verdicts that another order of the
    events closer than epsilon would change (their alternatives), which the trace cannot settle."""
    if not possible:
        return ""
    if possible == failures:
        return ", each only possible: another order of events closer than epsilon would pass it"
    return f", {possible} of them only possible (another order of events closer than epsilon would pass them)"


def _case(suite: ET.Element, con, sut: str, name: str, failures: list[dict], note: str) -> None:
    case = ET.SubElement(suite, "testcase", classname=sut, name=name, time="0")
    if failures:
        kinds = sorted({f["failure"] for f in failures})
        traces = sorted({f["trace_id"] for f in failures})
        possible = sum(not f["certain"] for f in failures)
        failure = ET.SubElement(case, "failure", type=",".join(kinds),
                                message=f"{len(failures)} {'/'.join(kinds)} in {len(traces)} trace(s) of {sut}"
                                        + _possible(possible, len(failures)))
        failure.text = _failure_text(con, failures)
    ET.SubElement(case, "system-out").text = note


def junit(con) -> ET.ElementTree:
    """The JUnit document of the store's last analysis."""
    cursor = con.execute(render_query("junit_failures"))
    columns = [d[0] for d in cursor.description]
    failing = defaultdict(list)
    for row in cursor.fetchall():
        r = dict(zip(columns, row))
        failing[(r["sut"], r["property_id"])].append(r)
    suites, per_sut = ET.Element("testsuites", name="untimely"), {}
    for sut, family, property_id, verdicts, fn, fp in con.execute(render_query("junit_cases")).fetchall():
        if sut not in per_sut:
            per_sut[sut] = ET.SubElement(suites, "testsuite", name=sut)
            bad = failing[(sut, None)]
            _case(per_sut[sut], con, sut, "outcome", bad, f"{len(bad)} hung or crashed trace(s)")
        _case(per_sut[sut], con, sut, property_id, failing[(sut, property_id)],
              f"{family}: {verdicts} verdicts, {fn} FN, {fp} FP")
    for suite in suites:
        cases = suite.findall("testcase")
        suite.set("tests", str(len(cases)))
        suite.set("failures", str(sum(c.find("failure") is not None for c in cases)))
        suite.set("errors", "0")
        suite.set("skipped", "0")
        suite.set("time", "0")
    for total in ("tests", "failures", "errors"):
        suites.set(total, str(sum(int(s.get(total)) for s in suites)))
    ET.indent(suites)
    return ET.ElementTree(suites)


def _write(tree: ET.ElementTree, path: Path) -> None:
    make_folder(path.resolve().parent, "the JUnit file")
    try:
        tree.write(path, encoding="utf-8", xml_declaration=True)
    except OSError as e:
        raise UntimelyError(f"--junit {str(path)!r}: cannot write it: {e.strerror}; the verdicts are stored, "
                            "pass a writable path") from None
    print(f"\nJUnit results written to {path}")


def check_path(path: Path | None) -> None:
    if path and path.is_dir():
        raise UntimelyError(f"--junit {str(path)!r} is a folder; give the path of the XML file to write, "
                            f"e.g. {str(path / 'untimely.xml')!r}")


def gate(db: str, path: Path | None, kinds: list[str]) -> list[str]:
    """The JUnit file written to `path` (when given); what the judged traces show of `kinds`."""
    con = connect(db, read_only=True)
    try:
        if path:
            _write(junit(con), path)
        counts = dict(zip(FAIL_ON, bad_trace_sums(con, list(FAIL_ON.values()))))
    finally:
        con.close()
    return [f"{counts[k]} trace(s) {k}" for k in kinds if counts[k]]

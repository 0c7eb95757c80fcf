"""`untimely analyze`: verdicts (re)materialised from the stored traces, Tables II-IV printed;
then, when asked, the JUnit file and the --fail-on gate of a CI server."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from harness import DEFAULT_EPSILON_S
from harness.analysis import analyzer
from harness.commands import options
from harness.report import junit

NAME = "analyze"
HELP = "(re)materialise verdicts from the stored traces and print Tables II-IV"


@dataclass(frozen=True)
class AnalyzeRequest:
    properties: str | None = None
    interface: str | None = None
    epsilon: float | None = None  # default: the last analysis's
    junit: str | None = None
    fail_on: str = ""
    db: str = options.DEFAULT_DB_TEXT


Request = AnalyzeRequest


def arguments(c) -> None:
    c.add_argument("--properties", help="properties file (default: properties.toml of the campaign's mission)")
    c.add_argument("--interface", help="interface description the properties name "
                                       "(default: interface.toml beside the properties file)")
    c.add_argument("--epsilon", type=options.SECONDS,
                   help=f"seconds within which near events may be reordered (default: the last analysis's, "
                        f"else {DEFAULT_EPSILON_S})")
    c.add_argument("--junit", metavar="FILE", help="also write the verdicts as JUnit XML for a CI server: a test "
                   "case per variant and property, failures for FN, FP, hung and crashed traces")
    c.add_argument("--fail-on", metavar="KINDS", default=AnalyzeRequest.fail_on, help="comma-separated among fn, fp, hung, "
                   "crashed: exit with status 1 when any judged trace shows one (a CI gate; default: never)")
    options.db(c)


def execute(request: AnalyzeRequest) -> int:
    kinds = junit.fail_on_kinds(request.fail_on)
    out = Path(request.junit) if request.junit else None
    junit.check_path(out)  # refused before the analysis, not after it
    status = analyzer.main(request.db, request.properties, request.interface, request.epsilon)
    found = junit.gate(request.db, out, kinds)
    if found:
        print(f"--fail-on {request.fail_on}: {', '.join(found)}")
        return 1
    return status

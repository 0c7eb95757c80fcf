"""docs/reference/ specifies every file a user writes: each key the loaders accept, each step of
the mission language, each table of the schema and each view, each verdict, each protocol op
and each command is named on its page (a key added to a loader without its documentation fails)."""
import re

import pytest

from harness import ROOT, SQL_DIR
from harness.sut.roscommon.mapping import TERMINAL_STATUSES
from harness.cli import _parser
from harness.target.suts import KEYS as SUT_KEYS
from harness.store.sql import VERDICTS
from harness.target.interface import INTERFACE_KEYS, SERVICE_KINDS
from harness.target.property_types import property_types

PROPERTY_TYPES = list(property_types())
from harness.target.layer_file import CHECKING, DEFECT_KINDS, INTERRUPTING, LAYER_KEYS, REJECTING

REFERENCE = ROOT / "docs" / "reference"


def page(name: str) -> str:
    return (REFERENCE / name).read_text()


def named(text: str, word: str) -> bool:
    """`word` appears as code: in backticks, alone or at the start of a longer code span."""
    left = r"\b" if word[0].isalnum() or word[0] == "_" else ""
    right = r"\b" if word[-1].isalnum() or word[-1] == "_" else ""
    return re.search(rf"`[^`\n]*{left}{re.escape(word)}{right}[^`\n]*`", text) is not None


@pytest.mark.parametrize("name, words", [
    ("interface.md", sorted({k for keys in INTERFACE_KEYS.values() for k in keys} | set(SERVICE_KINDS))),
    ("properties.md", ["id", "family", "type", "x", *sorted({p for ps in property_types().values() for p in ps}),
                       *PROPERTY_TYPES]),
    ("layer.md", [*sorted(LAYER_KEYS), *CHECKING, *REJECTING, *INTERRUPTING, *DEFECT_KINDS, "after", "while", "by",
                  "pairs", "checks", "domain",
                  "start_s", "run_s", "bounds", "rover", "rock", "heading_deg", "radius"]),
    ("suts.md", [*SUT_KEYS, "{python}", "{mission}", "{root}", "UNTIMELY_SLOT", "action", "services", "status_codes",
                 "heartbeat_stale_s", "world_topic", "internal_topic", "ping_topic", "pong_topic",
                 *TERMINAL_STATUSES]),
    ("mission-language.md", ["send", "wait", "sleep", "as", "all", "timeout="]),
    ("verdicts.md", [*VERDICTS, "unknown", "margin_s", "suspicious", "c_holds", *PROPERTY_TYPES]),
    ("protocol.md", ["hello", "request", "ping", "bye", "reply", "pong", "internal", "world", "error",
                     "time_scale", "caps"]),
])
def test_every_key_is_on_its_page(name, words):
    text = page(name)
    missing = [w for w in words if not named(text, w)]
    assert not missing, f"docs/reference/{name} does not name {missing}"


def test_every_table_and_view_of_the_store_is_specified():
    tables = re.findall(r"create table if not exists (\w+)", (SQL_DIR / "schema.sql").read_text())
    views = [p.stem for p in (SQL_DIR / "views").glob("*.sql") if p.stem not in ("wilson", "shared_codes")]
    text = page("store.md") + (ROOT / "docs" / "analyzer.md").read_text()
    missing = [n for n in tables + views if not named(text, n)]
    assert not missing, f"docs/reference/store.md (or docs/analyzer.md, which it links) lacks {missing}"


def test_every_command_is_listed():
    commands = _parser()._subparsers._group_actions[0].choices
    text = page("commands.md")
    assert not [c for c in commands if not named(text, c)]

"""Where the suite's files are. Test modules sit one or two folders deep (tests/<area>/), so a path
relative to a test's own file would break when it moves: every test finds the data folders here."""
from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]
ROOT = TESTS.parent
SUPPORT = TESTS / "support"
# The fixture data, kept at the top of tests/ whatever area uses it.
ADAPTERS = TESTS / "adapters"
BAGS = TESTS / "bags"
FINGERPRINTS = TESTS / "fingerprints"
GENOM = TESTS / "genom"
JUNIT = TESTS / "junit"
STORES = TESTS / "stores"
TRACES = TESTS / "traces"

import sys
from pathlib import Path

# The browser test judges the store that tests/test_report.py builds, one folder up.
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

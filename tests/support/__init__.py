"""What the tests share, imported as a library: `from tests.support.campaigns import fake_runner`.
No test module imports another (docs/contributing.md; tests/project/test_suite_layout.py checks it)."""

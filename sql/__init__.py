"""The SQL of the bench, installed as the package data `harness.sql` (pyproject.toml)."""

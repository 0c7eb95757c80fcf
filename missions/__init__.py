"""The example targets, installed as the package data `harness.missions` (pyproject.toml)."""

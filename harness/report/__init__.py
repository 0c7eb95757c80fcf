"""`python -m harness report`: HTML pages and CSV tables from the DuckDB store alone (read-only).
build.py writes the report; this package's __init__ imports nothing, so that the worker
processes writing trace pages import only what those pages need (no DuckDB, no Arrow)."""

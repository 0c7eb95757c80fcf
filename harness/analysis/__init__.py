"""Judging stored traces: oracles, the analyzer, the judge of one trace, provenance, explanations, diffs."""

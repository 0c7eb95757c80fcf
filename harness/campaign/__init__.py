"""Campaigns: mutants run on variants (campaign), ad-hoc runs (adhoc), shrunk reproducers (shrink)."""

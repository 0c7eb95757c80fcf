"""The bench's commands: a module each, importing its implementation directly (so the import
contract sees every command), with its NAME and HELP, its flags (`arguments`), its typed
`Request` (the class of its parsed arguments, named for the command: AnalyzeRequest, CampaignRequest,
...) and `execute(request)`. `harness.cli` parses the command line into a Request; nothing
below this package sees argparse."""
from __future__ import annotations

from harness.commands import (analyze, campaign, diff, explain, export, import_, init, merge, report, run, shrink,
                              sql)

# In the order `untimely --help` lists them.
COMMANDS = (run, campaign, merge, init, shrink, analyze, diff, explain, report, import_, export, sql)

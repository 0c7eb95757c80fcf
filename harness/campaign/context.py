"""What every step of a campaign shares, made once by `campaign.main`: the store, the target, the
campaign's record, the transports of its SUTs (the run setup) and the executor of its runs. The
campaign, its focused rounds, its shrinks and `campaign --shrink`'s representatives take this one
object rather than a dozen arguments each."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from harness.dispatch.executor import Executor
from harness.dispatch.description import Setup
from harness.store.record import CampaignRecord
from harness.target.interface import Interface, Property
from harness.target.mission import Mission
from harness.target.script import Script


@dataclass
class CampaignContext:
    con: object  # the store's connection; only this process writes to it
    db: str  # the store's path, as the user gave it (messages name it)
    target: Mission
    golden: Script
    golden_text: str  # the golden script as its file holds it, read once: the campaign stores this text
    properties: list[Property]
    config: CampaignRecord  # the campaign's record (campaigns.config)
    setup: Setup  # how each SUT is reached: the transports' runner, files and external definitions
    executor: Executor
    jobs: int
    cluster: str | None = None  # --cluster: runs on Dask
    shrink_to: Path | None = None  # where shrunk scripts go; None: no shrinking
    campaign_id: int | None = None  # once the campaign is found in the store or created
    allow_code_change: bool = False  # resume a campaign that other code of the bench made

    @property
    def interface(self) -> Interface:
        return self.target.interface

    @property
    def mission(self) -> Path:
        return self.target.folder

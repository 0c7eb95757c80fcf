"""`untimely import FILE --interface FILE`: traces from elsewhere into the store as a campaign
(docs/reference/store.md). A file of events is read by the store (harness/store/importer.py);
ROS bags are parsed by the ROS integration (harness/sut/bags) into the same rows, which the store
then checks and writes alike: the store itself knows nothing of ROS."""
from __future__ import annotations

from pathlib import Path

from harness.store import campaign_reads
from harness.store.database import connect
from harness.store.importer import ImportRows, import_file, import_rows
from harness.sut.bags import is_bag, read_bags
from harness.target.interface import Interface, load_interface
from harness.textable import counted


def import_path(con, path: str | Path, interface: Interface, ros: str | None = None) -> tuple[int, int, int]:
    """Events from a file of events, or from bags (`ros`: their mapping file, else ros.toml beside
    the interface): (campaign_id, first trace id, traces)."""
    path = Path(path)
    if is_bag(path):
        return import_rows(con, path, interface, ImportRows(*read_bags(path, interface, ros)))
    return import_file(con, path, interface)


def main(db: str, file: str, interface: str, ros: str | None = None) -> int:
    """`import FILE --interface FILE [--ros FILE]`."""
    interface = load_interface(interface)
    con = connect(db)
    path = Path(file)
    campaign_id, first, count = import_path(con, path, interface, ros)
    events = campaign_reads.event_count(con, first, first + count - 1)
    print(f"Imported {counted(count, 'trace')} ({counted(events, 'event')}) from {path} as campaign {campaign_id}, "
          f"trace ids {first}-{first + count - 1}. Run python -m harness analyze --db {db} to judge them.")
    return 0

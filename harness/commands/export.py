"""`untimely export DIR`: every table and view of the store as files, with a manifest."""
from __future__ import annotations

from dataclasses import dataclass

from harness.commands import options
from harness.store import export

NAME = "export"
HELP = "write every table and view of the store as Parquet or CSV files, with a manifest"


@dataclass(frozen=True)
class ExportRequest:
    dir: str
    format: str = "parquet"
    db: str = options.DEFAULT_DB_TEXT


Request = ExportRequest


def arguments(c) -> None:
    c.add_argument("dir", help="output folder, created if missing")
    c.add_argument("--format", choices=("parquet", "csv"), default=ExportRequest.format,
                   help="file format (default: %(default)s)")
    options.db(c)


def execute(request: ExportRequest) -> int:
    return export.main(request.db, request.dir, request.format)

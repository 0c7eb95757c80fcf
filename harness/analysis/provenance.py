"""What an analysis was made from (the `analyses` and `analysis_files` tables of sql/schema.sql,
written by harness.store.analyses).

Each analysis records the SHA-256 of its properties file, of the interface beside it and of every
template under sql/; `stale_files` says which of them no longer match the files on disk, so that
the report can tell when the stored verdicts are out of date. The default properties of `analyze`
are the ones of the mission the campaign was made from.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

from harness import DEFAULT_EPSILON_S, SQL_DIR
from harness.errors import StoreError
from harness.store import analysis_reads
from harness.store.record import records
from harness.target.mission import INTERFACE_FILE, PROPERTIES_FILE


def _sha256(path: Path) -> str | None:
    try:
        return hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError:
        return None


def templates() -> list[Path]:
    """The templates the verdicts and the analyzer's views are made from; not the report's queries
    (sql/report/), which change no stored value."""
    return [t for folder in ("oracles", "views") for t in sorted((SQL_DIR / folder).glob("*.sql"))]


def sources(properties_file: Path | None, interface_file: Path | None = None) -> list[tuple[str, str, str]]:
    """(role, path, sha256) of every file that decides the verdicts (the interface: beside the
    properties unless given); none for properties given in code."""
    if properties_file is None:
        return []
    files = [("properties", properties_file),
             ("interface", interface_file or properties_file.parent / INTERFACE_FILE)]
    files += [("template", t) for t in templates()]
    return [(role, str(path.resolve()), _sha256(path)) for role, path in files]


def _in_package(path: str) -> Path:
    """A template's path under sql/ (oracles/pc.sql), wherever the installation that recorded it was."""
    return Path(*Path(path).parts[-2:])


def stale_files(con) -> list[tuple[str, str]]:
    """(role, path) of the last analysis's files that changed or vanished since it ran. Templates are
    compared by content with this installation's, whatever folder the analysing one was in (a CI
    wheel's, then a checkout's), and named as under sql/ (sql/oracles/pc.sql)."""
    found = analysis_reads.last_analysis_files(con)
    stale = [(role, path) for role, path, sha in found if role != "template" and _sha256(Path(path)) != sha]
    recorded = {_in_package(path): sha for role, path, sha in found if role == "template"}
    current = {t.relative_to(SQL_DIR): t for t in templates()}
    if found:  # a template changed, vanished, or added since the analysis changes what the oracles may do
        stale += [("template", f"sql/{name}") for name in sorted(set(recorded) | set(current))
                  if name not in current or recorded.get(name) != _sha256(current[name])]
    return stale


def last_epsilon(con) -> float:
    """The epsilon of the last analysis (DEFAULT_EPSILON_S before the first one)."""
    found = analysis_reads.last_analysis_epsilon(con)
    return DEFAULT_EPSILON_S if found is None else found


def default_properties(con) -> Path:
    """The properties file of the target the last campaign, run or import was made from."""
    tried = []
    for _, mission, record in reversed(records(con)):
        candidate = record.target(mission) / PROPERTIES_FILE
        if candidate.is_file():
            return candidate
        tried.append(str(candidate))
    raise StoreError(f"the store records no target folder with a properties file ({', '.join(tried) or 'no campaign'}"
                     "); pass --properties FILE")

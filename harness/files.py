"""Files a user hands the bench or asks it to write: one message per way they go wrong."""
from __future__ import annotations

from pathlib import Path

from harness.errors import InputFileError, UntimelyError


def read_text(path: str | Path) -> str:
    """A text file's contents; one that is not UTF-8 is refused with the line of its first bad byte."""
    return decode(Path(path), Path(path).read_bytes())


def decode(path: str | Path, data: bytes) -> str:
    """The text of a file's bytes; bytes that are not UTF-8 are refused naming the file and line."""
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        raise InputFileError(path, line, f"not UTF-8 (byte 0x{data[e.start]:02x}); save the file as UTF-8") from None


def make_folder(path: str | Path, what: str) -> Path:
    """Create a folder (and its parents) the bench writes into; a read-only or full place is refused."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise UntimelyError(f"cannot create the folder {str(path)!r} for {what}: {e.strerror}; "
                            "pass a writable place") from None
    return path

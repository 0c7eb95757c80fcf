"""Files a user hands the bench or asks it to write: one message per way they go wrong."""
from __future__ import annotations

import errno
import tomllib
from pathlib import Path

from harness.errors import InputFileError, UntimelyError

BOM = "\ufeff"  # what Notepad puts before UTF-8 text: not part of the text


def read_bytes(path: str | Path, missing: str = "file not found; pass an existing file") -> bytes:
    """A file's bytes; `missing` is the message for a file that is not there. A folder, a symbolic
    link that loops or an unreadable file is refused saying which."""
    try:
        return Path(path).read_bytes()
    except FileNotFoundError:
        raise InputFileError(path, "", missing) from None
    except IsADirectoryError:
        raise InputFileError(path, "", "is a folder, not a file; pass the file itself") from None
    except OSError as e:
        if e.errno == errno.ELOOP:
            raise InputFileError(path, "", "is a symbolic link that loops; point it at a real file") from None
        raise InputFileError(path, "", f"cannot read it: {e.strerror}; pass a readable file") from None


def existing_file(path: str | Path, missing: str = "file not found; pass an existing file") -> Path:
    """`path`, once known to be a file: else the message of read_bytes (missing, a folder, a loop)."""
    if not Path(path).is_file():
        read_bytes(path, missing)
    return Path(path)


def read_text(path: str | Path, missing: str = "file not found; pass an existing file") -> str:
    """A text file's contents; one that is not UTF-8 is refused with the line of its first bad byte."""
    return decode(path, read_bytes(path, missing))


def decode(path: str | Path, data: bytes) -> str:
    """The text of a file's bytes, without a leading byte-order mark; bytes that are not UTF-8 are
    refused naming the file and line."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        raise InputFileError(path, line, f"not UTF-8 (byte 0x{data[e.start]:02x}); save the file as UTF-8") from None
    return text.removeprefix(BOM)


def read_toml(path: str | Path, missing: str = "file not found; pass an existing file") -> tuple[dict, str]:
    """A TOML data file's contents and its text (for the lines of messages)."""
    text = read_text(path, missing)
    return parse_toml(path, text), text


def parse_toml(path: str | Path, text: str) -> dict:
    """The TOML `text` read from `path` (named in messages)."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise InputFileError(path, "", f"not valid TOML: {e}") from None


def make_folder(path: str | Path, what: str) -> Path:
    """Create a folder (and its parents) the bench writes into; a read-only or full place is refused."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise UntimelyError(f"cannot create the folder {str(path)!r} for {what}: {e.strerror}; "
                            "pass a writable place") from None
    return path

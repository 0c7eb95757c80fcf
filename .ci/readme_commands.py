"""Run every command the README shows, verbatim, in a fresh clone of this repository.

The commands are the lines of the README's ``` blocks, in order (a `#` starts a comment, as
in a shell); a block fenced ```text holds templates with placeholders and is not run. `make test` is left out: `.ci/run` runs it already, and running the suite from
inside the suite would not end. Stops at the first command that fails, printing its output.

    python3 .ci/readme_commands.py            # from the repository, after committing
"""
from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LEFT_OUT = {"make test": "run by .ci/run itself"}


def commands(readme: str) -> list[str]:
    """The README's command lines, in order: the non-blank lines of its ``` blocks but ```text."""
    found, fence = [], None  # fence: the info string of the block we are in, None outside
    for line in readme.splitlines():
        if line.startswith("```"):
            fence = line[3:].strip() if fence is None else None
        elif fence not in (None, "text") and line.strip() and not line.strip().startswith("#"):
            found.append(line.strip())
    return found


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        clone = Path(tmp) / "untimely"
        subprocess.run(["git", "clone", "--quiet", str(ROOT), str(clone)], check=True)
        for command in commands((clone / "README.md").read_text()):
            bare = command.split("#")[0].strip()
            if bare in LEFT_OUT:
                print(f"-- skipped: {command}  ({LEFT_OUT[bare]})", flush=True)
                continue
            print(f"-- {command}", flush=True)
            done = subprocess.run(["bash", "-c", command], cwd=clone, capture_output=True, text=True)
            if done.returncode != 0:
                print(done.stdout[-4000:], done.stderr[-4000:], sep="\n", file=sys.stderr)
                print(f"README command failed with status {done.returncode}: {command}", file=sys.stderr)
                return 1
    print("every README command succeeded on a fresh clone")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

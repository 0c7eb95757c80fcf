"""`untimely init DIR [--from-genom FILE.gen [--include DIR]...]`: a target folder to start from,
that already runs.

It writes interface.toml, properties.toml and golden.mission (commented, from a small example robot
or from what a GenoM3 description states: harness.target.genom.derive), standin.toml (the rules of
the stand-in layer: those the properties state), suts.toml, and adapter.py: a standard-library
untimely/1 adapter that stands in for the layer until the user connects theirs. The files are
written into a scratch folder beside DIR and moved in once all are written, so a failure (a
read-only place, a full disk) leaves no half-written target behind.
"""
from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from harness.errors import UntimelyError
from harness.files import make_folder
from harness.target.draft import (Draft, aib, golden_text, interface_text, pex, pre, properties_text,
                                  standin_text)
from harness.target.genom.derive import from_genom
from harness.target.mission import GOLDEN_FILE, INTERFACE_FILE, PROPERTIES_FILE, SUTS_FILE

SKELETON = Path(__file__).resolve().parent / "skeleton"
WRITTEN = (INTERFACE_FILE, PROPERTIES_FILE, GOLDEN_FILE, "standin.toml", SUTS_FILE, "adapter.py")


def example() -> Draft:
    """A two-module robot whose properties show the three families a GenoM layer states."""
    draft = Draft("an example robot: replace its modules and services by your layer's",
                  {"base": {"Init": "init", "SetSpeed": "control", "Move": "exec", "Stop": "exec"},
                   "camera": {"Init": "init", "Capture": "exec", "Stop": "exec"}})
    for module in draft.modules:
        draft.properties.append(pex(draft, module, "Init"))
    draft.properties.append(aib("base.Move", ["base.Move", "base.Stop"]))
    draft.properties.append(aib("camera.Capture", ["camera.Capture", "camera.Stop"]))
    draft.properties.append(pre("base.Move", ["base.SetSpeed"]))
    return draft


def new_target_folder(folder: Path, names: tuple[str, ...]) -> None:
    """Create the folder `init` writes `names` into; never over a file of it, nor through a link there
    (even one to nothing)."""
    existing = [name for name in names if os.path.lexists(folder / name)]
    links = [f"{name} (a link to {os.readlink(folder / name)})" for name in existing if (folder / name).is_symlink()]
    if links:
        raise UntimelyError(f"{folder} holds {', '.join(links)}; `untimely init` writes new files and never "
                            "through a link: remove the link, or give another DIR")
    if existing:
        raise UntimelyError(f"{folder} already holds {', '.join(existing)}; `untimely init` writes a new target "
                            "folder: give another DIR, or move those files away")
    make_folder(folder, "the target")


def write_all_or_none(folder: Path, texts: dict[str, str], copies: dict[str, Path]) -> list[Path]:
    """Write a new target folder's files (texts, and copies of the given files), all of them or none."""
    names = tuple(texts) + tuple(copies)
    new_target_folder(folder, names)
    try:
        with tempfile.TemporaryDirectory(prefix=".untimely-init-", dir=folder) as scratch:
            for name, text in texts.items():
                Path(scratch, name).write_text(text)
            for name, source in copies.items():
                shutil.copyfile(source, Path(scratch, name))
            for name in names:
                os.replace(Path(scratch, name), folder / name)  # a link put there meanwhile is replaced, not followed
    except OSError as e:
        for name in names:  # a move that failed half-way: take back what it moved
            if (folder / name).is_file() and not (folder / name).is_symlink():
                (folder / name).unlink()
        raise UntimelyError(f"cannot write the target {folder}/: {e.strerror or e}; nothing was written: pass a "
                            "writable place with free space") from None
    return [folder / name for name in names]


def write(folder: Path, draft: Draft) -> list[Path]:
    """Write the target folder, all files or none; refuses to overwrite any file of it."""
    texts = {INTERFACE_FILE: interface_text(draft), PROPERTIES_FILE: properties_text(draft),
             GOLDEN_FILE: golden_text(draft), "standin.toml": standin_text(draft)}
    return write_all_or_none(folder, texts, {name: SKELETON / name for name in (SUTS_FILE, "adapter.py")})


def scaffold(folder: Path, genom: str | None = None, include: list[str] = ()) -> int:
    """`init FOLDER [--from-genom FILE.gen [--include DIR]...]`."""
    if genom and not Path(genom).is_file():
        raise UntimelyError(f"--from-genom {genom!r}: no such file; give a GenoM3 .gen file")
    if include and not genom:
        raise UntimelyError("--include is for the #include lines of --from-genom FILE.gen; give both or neither")
    missing = [d for d in include if not Path(d).is_dir()]
    if missing:
        raise UntimelyError(f"--include {missing[0]!r}: no such folder; give the folder #include searches")
    draft = from_genom(Path(genom), [Path(d) for d in include]) if genom else example()
    write(folder, draft)
    print(f"wrote the target {folder}/ from {draft.source}: {', '.join(WRITTEN)}")
    print(f"  {sum(len(s) for s in draft.modules.values())} services in {len(draft.modules)} modules, "
          f"{len(draft.properties)} properties")
    for note in draft.notes:
        print(f"  not derived: {note}")
    print(f"next: untimely run {folder}/golden.mission --sut adapter\n"
          f"      untimely campaign --mission {folder} --sut adapter --mutants 20")
    return 0

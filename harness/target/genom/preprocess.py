"""The C preprocessor pass genom3 makes over a .gen file before reading it (pcpp, a C99
preprocessor in pure Python): `#include` searched beside the including file, then in the `-I`
folders; `#define` and `#if`; comments removed. `#pragma` lines are kept aside: `#pragma provides`
means what a `provides` of every component means; the others concern genom3's build, not the
interface (derive.py names them as ignored). Every line of the result keeps the file and line it came from."""
from __future__ import annotations

import io
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from pcpp import Action, OutputDirective, Preprocessor

from harness.errors import InputFileError
from harness.files import read_text

LINE_MARK = re.compile(r'#line (\d+) "((?:[^"\\]|\\.)*)"')
MAX_OPENS = 64  # opening one file this often means an #include loop without an include guard


@dataclass(frozen=True)
class Origin:
    file: str
    line: int

    def __str__(self) -> str:
        return f"{Path(self.file).name}:{self.line}"


@dataclass
class Source:
    """The preprocessed text, its lines' origins (text line n is origins[n - 1]) and its pragmas."""
    text: str
    origins: list[Origin]
    pragmas: list[tuple[Origin, str]] = field(default_factory=list)


class _Pass(Preprocessor):
    def __init__(self, includes: list[Path]):
        super().__init__()
        self.line_directive = "#line"
        self.pragmas: list[tuple[Origin, str]] = []
        self.opens: dict[str, int] = {}
        for folder in includes:
            self.add_path(str(folder))

    def on_error(self, file, line, msg):
        raise InputFileError(os.path.abspath(file), line, f"{msg}; genom3's preprocessor would refuse it too: "
                             "fix the line")

    def on_include_not_found(self, is_malformed, is_system_include, curdir, includepath):
        directive = self.lastdirective
        raise InputFileError(os.path.abspath(directive.source), directive.lineno, f"#include {includepath!r} not "
                             "found beside the file nor in any --include folder; give its folder with --include DIR "
                             "(-I DIR)")

    def on_file_open(self, is_system_include, includepath):
        self.opens[includepath] = self.opens.get(includepath, 0) + 1
        if self.opens[includepath] > MAX_OPENS:
            raise InputFileError(includepath, "", f"included {MAX_OPENS} times: an #include loop; give the file an "
                                 "include guard (#ifndef NAME / #define NAME ... #endif) or remove the loop")
        return super().on_file_open(is_system_include, includepath)

    def on_directive_unknown(self, directive, toks, ifpassthru, precedingtoks):
        if directive.value == "pragma":
            words = "".join(t.value for t in toks).strip()
            self.pragmas.append((Origin(os.path.abspath(directive.source), directive.lineno), words))
            raise OutputDirective(Action.IgnoreAndRemove)
        raise InputFileError(os.path.abspath(directive.source), directive.lineno, f"unknown directive "
                             f"#{directive.value}; genom3's preprocessor knows #include, #define, #if..., #pragma")


def preprocess(path: Path, includes: list[Path]) -> Source:
    """The .gen file after the C preprocessor, refused naming file and line where cpp would stop."""
    text = read_text(path)
    unterminated = _unterminated_comment(text)
    if unterminated:
        raise InputFileError(path, unterminated, "a /* comment that never ends; close it with */")
    cpp = _Pass([path.parent, *includes])
    try:
        cpp.parse(text, str(path))
        out = io.StringIO()
        cpp.write(out)
    except RecursionError:
        raise InputFileError(path, "", "#include nests too deep (a loop?); give the included files include "
                             "guards") from None
    return _located(out.getvalue(), str(path), cpp.pragmas)


def _unterminated_comment(text: str) -> int | None:
    """The line of a `/*` that no `*/` closes (outside strings and // comments), else None."""
    tokens = re.finditer(r'"(?:[^"\\\n]|\\.)*"|//[^\n]*|/\*.*?\*/|/\*', text, re.S)
    for token in tokens:
        if token.group(0) == "/*":
            return text.count("\n", 0, token.start()) + 1
    return None


def _located(output: str, first: str, pragmas: list) -> Source:
    """The preprocessor's output with its #line marks blanked, and where each line came from."""
    lines, origins = [], []
    file, line = os.path.abspath(first), 1
    for text in output.split("\n"):
        mark = LINE_MARK.fullmatch(text.strip())
        if mark:
            line, file = int(mark.group(1)), os.path.abspath(mark.group(2))
            lines.append("")
            origins.append(Origin(file, line))
            continue
        lines.append(text)
        origins.append(Origin(file, line))
        line += 1
    return Source("\n".join(lines), origins, pragmas)

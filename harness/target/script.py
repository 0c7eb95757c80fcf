"""The mission-script language (docs/reference/mission-language.md): parse, validate and render scripts.

    send MODULE.SERVICE [name=value ...] [as HANDLE]   # non-blocking request
    cancel HANDLE [as HANDLE]                          # non-blocking cancel of a goal sent as HANDLE
    wait HANDLE|all [timeout=SECONDS]                  # block until final replies
    sleep SECONDS                                      # simulated seconds

Parsing checks the shape of each line; validation checks it against an interface
(known modules, services, arguments, handles sent on an earlier line). Argument values are
not checked: a value outside its domain (harness/target/domains.py) — out of range, nan, of
the wrong type, or a required argument left out — is the layer's to reject with `bad_params`,
which is part of what the bench tests (value mutants must stay runnable).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, replace
from pathlib import Path

from harness.errors import ScriptError
from harness.files import read_text
from harness.schema import cut
from harness.target.domains import NON_FINITE
from harness.target.interface import Interface

HANDLE_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*$")
SERVICE_RE = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\.([A-Za-z_][A-Za-z0-9_]*)$")
# A cancel of a goal of M.S is a request of the service M.S_cancel, whose one argument (added by the
# executive, never written in a script) is the request id of the cancelled goal's request.
CANCEL_SUFFIX = "_cancel"
CANCEL_GOAL_ARG = "goal"


def cancel_service(service: str) -> str:
    """The service whose request cancels a goal of `service` ("arm.move" -> "arm.move_cancel")."""
    return service + CANCEL_SUFFIX


@dataclass(frozen=True)
class Step:
    line: int
    op: str  # send | cancel | wait | sleep
    service: str | None = None  # "module.Service" (send)
    args: tuple[tuple[str, str], ...] = ()  # (name, text value) in script order (send)
    handle: str | None = None  # the 'as' name (send, cancel), the awaited handle or "all" (wait)
    seconds: float | None = None  # sleep duration, wait timeout
    comment: str = ""
    cancelled: str | None = None  # the handle of the goal a cancel cancels (cancel)

    @property
    def module(self) -> str | None:
        return self.service.split(".")[0] if self.service else None

    def render(self) -> str:
        if self.op == "send":
            words = ["send", self.service, *(f"{k}={v}" for k, v in self.args)]
            if self.handle:
                words += ["as", self.handle]
        elif self.op == "cancel":
            words = ["cancel", self.cancelled] + (["as", self.handle] if self.handle else [])
        elif self.op == "wait":
            words = ["wait", self.handle]
            if self.seconds is not None:
                words.append(f"timeout={_number(self.seconds)}")
        else:
            words = ["sleep", _number(self.seconds)]
        text = " ".join(words)
        return f"{text}  # {self.comment}" if self.comment else text

    def __repr__(self) -> str:
        return f"<Step line {self.line}: {self.render()}>"


@dataclass(frozen=True)
class Script:
    steps: tuple[Step, ...]
    source: str = "<script>"

    def render(self) -> str:
        return "".join(step.render() + "\n" for step in self.steps)

    def renumbered(self, source: str | None = None) -> "Script":
        """The same steps with line numbers of the rendered text (after a mutation)."""
        steps = tuple(replace(s, line=n) for n, s in enumerate(self.steps, 1))
        return Script(steps, source or self.source)

    def __repr__(self) -> str:
        return f"<Script {self.source}: {len(self.steps)} steps>"


MAX_SECONDS = 86_400.0  # of a sleep or a wait's timeout


def _number(value: float) -> str:
    return f"{value:g}"


def _seconds(source, line, text, what) -> float:
    try:
        value = float(text)
    except ValueError:
        value = None
    if value is None or not value > 0 or value != value or value == float("inf"):
        raise ScriptError(source, line, f"{what} {cut(text)} is not a positive number of seconds")
    if value > MAX_SECONDS:  # a real-time run would wait for it: a typo must not hang the bench
        raise ScriptError(source, line, f"{what} {cut(text)} is longer than a day ({MAX_SECONDS:g} s); "
                                        "give a duration in seconds up to that")
    return value


def _as_handle(source: str, n: int, rest: list[str]) -> tuple[str | None, list[str]]:
    """The words before a closing `as HANDLE`, and that handle (None without `as`)."""
    if "as" not in rest:
        return None, rest
    at = rest.index("as")
    if at != len(rest) - 2 or not HANDLE_RE.match(rest[-1]) or rest[-1] == "all":
        raise ScriptError(source, n, f"'as' must end the line with one handle name, got {cut(' '.join(rest[at:]))}")
    return rest[-1], rest[:at]


def _parse_cancel(source: str, n: int, rest: list[str], comment: str) -> Step:
    handle, rest = _as_handle(source, n, rest)
    if len(rest) != 1 or not HANDLE_RE.match(rest[0]) or rest[0] == "all":
        raise ScriptError(source, n, f"'cancel' takes the handle of one goal and an optional 'as HANDLE', "
                                     f"got {cut(' '.join(rest))}")
    return Step(n, "cancel", handle=handle, cancelled=rest[0], comment=comment)


def _parse_line(source: str, n: int, text: str, comment: str) -> Step:
    words = text.split()
    op, rest = words[0], words[1:]
    if op == "cancel":
        return _parse_cancel(source, n, rest, comment)
    if op == "sleep":
        if len(rest) != 1:
            raise ScriptError(source, n, f"'sleep' takes one number of seconds, got {cut(' '.join(rest))}")
        return Step(n, "sleep", seconds=_seconds(source, n, rest[0], "sleep duration"), comment=comment)
    if op == "wait":
        if not rest or len(rest) > 2:
            raise ScriptError(source, n, f"'wait' takes a handle or 'all' and an optional timeout=S, got {cut(text)}")
        timeout = None
        if len(rest) == 2:
            if not rest[1].startswith("timeout="):
                raise ScriptError(source, n, f"unexpected {cut(rest[1])} after the handle; write timeout=SECONDS")
            timeout = _seconds(source, n, rest[1][len("timeout="):], "timeout")
        if rest[0] != "all" and not HANDLE_RE.match(rest[0]):
            raise ScriptError(source, n, f"{cut(rest[0])} is not a handle name (letters, digits, _)")
        return Step(n, "wait", handle=rest[0], seconds=timeout, comment=comment)
    if op == "send":
        if not rest or not SERVICE_RE.match(rest[0]):
            raise ScriptError(source, n, f"'send' needs MODULE.SERVICE first, got {cut(' '.join(rest[:1]))}")
        handle, rest = _as_handle(source, n, rest)
        args = []
        for word in rest[1:]:
            name, eq, value = word.partition("=")
            if not eq or not name or not value:
                raise ScriptError(source, n, f"argument {cut(word)} is not of the form name=value")
            args.append((name, value))
        return Step(n, "send", service=rest[0], args=tuple(args), handle=handle, comment=comment)
    raise ScriptError(source, n, f"unknown step {cut(op)}; a step is send, cancel, wait or sleep")


def parse(text: str, source: str = "<script>") -> Script:
    """Parse a script's text; raises ScriptError naming the line of a malformed step."""
    steps = []
    for n, raw in enumerate(text.split("\n"), 1):  # only \n ends a line: not U+2028 or a form feed in a comment
        body, _, comment = raw.partition("#")
        if body.strip():
            steps.append(_parse_line(source, n, body.strip(), comment.strip()))
    if not steps:
        raise ScriptError(source, 1, "the script has no steps; add send, cancel, wait or sleep lines")
    return Script(tuple(steps), source)


def step_text(step: Step) -> str:
    """A step as a mutation operation records it: its text without the comment."""
    return replace(step, comment="").render()


def _overflows(word: str) -> bool:
    """Whether a float argument's word is a number too large for a float (1e400), which a layer
    would read as infinity: a value a script means to be infinite is written inf."""
    try:
        value = float(word)
    except ValueError:
        return False  # a word that is no number is carried as text, the layer's to refuse
    return value in (float("inf"), float("-inf")) and word.strip().lower() not in NON_FINITE


def validate(script: Script, interface: Interface) -> None:
    """Raise ScriptError at the first step the interface cannot run."""
    src, handles = script.source, {}  # handle -> the send or cancel step it names
    for step in script.steps:
        if step.op == "wait" and step.handle != "all" and step.handle not in handles:
            raise ScriptError(src, step.line, f"wait on handle {cut(step.handle)}, which no earlier line sends")
        if step.op == "send":
            _check_send(src, step, interface)
        elif step.op == "cancel":
            _check_cancel(src, step, handles, interface)
        else:
            continue
        if step.handle in handles:
            raise ScriptError(src, step.line, f"handle {cut(step.handle)} already names the request "
                              f"on line {handles[step.handle].line}; choose a new name")
        if step.handle:
            handles[step.handle] = step


def _check_send(src: str, step: Step, interface: Interface) -> None:
    service = interface.services.get(step.service)
    if service is None:
        offered = [s.name for s in interface.services.values() if s.module == step.module]
        hint = (f"module {cut(step.module)} offers {', '.join(offered)}" if offered
                else f"known modules: {', '.join(interface.modules)}")
        raise ScriptError(src, step.line, f"unknown service {cut(step.service)}; {hint}")
    given = [name for name, _ in step.args]
    for name, word in step.args:
        arg = service.args.get(name)
        if arg is None:
            expected = ", ".join(service.args) or "no arguments"
            raise ScriptError(src, step.line, f"{step.service} has no argument {cut(name)}; it takes {expected}")
        if given.count(name) > 1:
            raise ScriptError(src, step.line, f"argument {cut(name)} is given twice")
        if arg.type == "float" and _overflows(word):
            raise ScriptError(src, step.line, f"argument {name}={cut(word)} overflows a 64-bit float (the "
                              "largest is about 1.8e308); write a number up to that, or inf for infinity")


def _check_cancel(src: str, step: Step, handles: dict[str, Step], interface: Interface) -> None:
    """A cancel names the goal of an action (an exec service) sent earlier, whose cancel service
    the interface declares."""
    goal = handles.get(step.cancelled)
    if goal is None:
        raise ScriptError(src, step.line, f"cancel of handle {cut(step.cancelled)}, which no earlier line sends")
    if goal.op != "send" or interface.services[goal.service].kind != "exec":
        what = "a cancel" if goal.op == "cancel" else f"{goal.service}, a {interface.services[goal.service].kind} service"
        raise ScriptError(src, step.line, f"cancel of handle {cut(step.cancelled)}, which names {what} (line "
                          f"{goal.line}); only the goal of an exec service (an action) can be cancelled")
    cancel = cancel_service(goal.service)
    if cancel not in interface.services:
        module, name = cancel.split(".")
        raise ScriptError(src, step.line, f"cancel of {goal.service} needs the service {cancel}, which the interface "
                          f"{interface.path} does not declare; add services.{name} = {{ kind = \"control\" }} to "
                          f"its [modules.{module}]")


# Why the simulated layer runs no cancel step: its activities end by a request of their module
# (an interrupting service), as the paper's layer's do; a cancel that no goal honours would be a lie.
SIMULATED_NO_CANCEL = ("the simulated layer (layer.toml) has no cancels; interrupt an activity with a request "
                       "of its module, or cancel goals on a ROS 2 target (docs/ros2.md)")


def refuse_cancels(script: Script, why: str) -> None:
    """Refuse a script with a cancel step where its layer offers no cancels (`why`)."""
    step = next((s for s in script.steps if s.op == "cancel"), None)
    if step is not None:
        raise ScriptError(script.source, step.line, f"cancel {step.cancelled}: {why}")


def load_script(path: str | Path, interface: Interface) -> Script:
    return script_of(read_text(path, "file not found; pass an existing mission script"), path, interface)


def script_of(text: str, path: str | Path, interface: Interface) -> Script:
    """The script a file of `path` holds as `text`, checked against the interface."""
    script = parse(text, str(path))
    validate(script, interface)
    return script

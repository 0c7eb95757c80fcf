"""The core knows no target: the Dala layer's modules, services, reply codes and variants live in
missions/dala (data, and the behaviour module its layer.toml names), never in the kernel, the
module framework, the layer, the executive, the workers, the campaign runner or the CLI.

What is checked is code: names and string literals, not comments or docstrings (prose may say
that an activity was interrupted)."""
import io
import re
import tokenize

from harness import DEFAULT_MISSION_DIR, ROOT
from harness.target.interface import load_interface
from harness.target.mission import load_layer

CORE = ("harness/sut/simulated/kernel.py", "harness/sut/simulated/module.py", "harness/sut/simulated/layer.py",
        "harness/target/layer_description.py", "harness/sut/simulated/host.py", "harness/sut/simulated/realtime.py",
        "harness/sut/executive.py", "harness/dispatch/workers.py",
        "harness/campaign/campaign.py", "harness/campaign/adhoc.py", "harness/cli.py", "harness/target/mission.py")


def dala_names() -> set[str]:
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    layer = load_layer(DEFAULT_MISSION_DIR)
    names = set(interface.modules) | {s.name for s in interface.services.values()} | set(interface.replies)
    names |= set(layer.variants) | set(layer.protections) | set(layer.defects)
    return names - {"ok"}  # the one reply code every interface has (docs/reference/interface.md)


def test_the_core_names_nothing_of_dala():
    names = dala_names()
    assert {"rflex", "TrackSpeedStart", "Stop", "wait_init", "interrupted_excl", "genom", "AIB"} <= names
    pattern = re.compile(r"(?<![\w.-])(" + "|".join(map(re.escape, sorted(names))) + r")(?![\w-])")
    found = [f"{path}:{token.start[0]}: {token.string}" for path in CORE for token in code_tokens(ROOT / path)
             if pattern.search(token.string)]
    assert found == []


def code_tokens(path):
    """Names and string literals; not comments, not triple-quoted strings (docstrings)."""
    kinds = {tokenize.NAME, tokenize.STRING, getattr(tokenize, "FSTRING_MIDDLE", tokenize.STRING)}
    for token in tokenize.generate_tokens(io.StringIO(path.read_text()).readline):
        if token.type in kinds and not token.string.lstrip("rbfuRBFU").startswith(('"""', "'''")):
            yield token


def test_the_check_finds_a_dala_literal(tmp_path):
    planted = tmp_path / "planted.py"
    planted.write_text('"""It was interrupted."""\n# rflex\ncode = "wait_init"\n')
    names = [t.string for t in code_tokens(planted) if t.string.strip('"') in dala_names()]
    assert names == ['"wait_init"']

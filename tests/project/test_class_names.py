"""A class name says one thing: no two classes of harness/ share a name, so a name read in a
traceback, a doc or a grep finds one class (issue 45)."""
import ast
from collections import defaultdict

from harness import ROOT

# Names still defined more than once, in files being reworked elsewhere; a name that comes to be
# defined once leaves this list.
LEFT: set[str] = set()


def definitions(folder) -> dict[str, list[str]]:
    """Class name -> the files (relative to `folder`) that define a class of that name, at any depth."""
    found = defaultdict(list)
    for path in sorted(folder.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.ClassDef):
                found[node.name].append(str(path.relative_to(folder)))
    return found


def test_no_class_name_is_defined_twice():
    twice = {name: files for name, files in definitions(ROOT / "harness").items() if len(files) > 1}
    assert set(twice) - LEFT == set(), f"give each its own name: {twice}"
    assert LEFT - set(twice) == set(), f"defined once now: take them out of LEFT: {LEFT - set(twice)}"


def test_a_name_defined_twice_is_found(tmp_path):
    (tmp_path / "a.py").write_text("class Request:\n    pass\n")
    (tmp_path / "b.py").write_text("def f():\n    class Request:\n        pass\n")
    (tmp_path / "c.py").write_text("class RunRequest:\n    pass\n")
    assert definitions(tmp_path) == {"Request": ["a.py", "b.py"], "RunRequest": ["c.py"]}

"""The store is the one gateway (issue 20): no Python file outside harness/store/ holds an SQL
statement that writes, the benchmarks' (bench/) included; the statements that write are in
harness/store/ or in sql/ templates."""
import ast
import re
from pathlib import Path

import pytest

from harness import ROOT

WRITES = re.compile(r"\b(insert\s+into|update\s+\w+(\s+as\s+\w+)?\s+set|delete\s+from|"
                    r"create\s+(or\s+replace\s+)?(temp\s+|temporary\s+)?(table|view|macro|index|schema|sequence)|"
                    r"drop\s+(table|view|macro|index|schema|sequence)|alter\s+(table|view))\b", re.I)
STORE = ROOT / "harness" / "store"


def _strings(tree: ast.AST):
    """Every string literal, f-strings' literal parts joined with a placeholder for their fields."""
    parts = {id(v) for node in ast.walk(tree) if isinstance(node, ast.JoinedStr) for v in node.values}
    for node in ast.walk(tree):
        if isinstance(node, ast.JoinedStr):
            yield node.lineno, "".join(v.value if isinstance(v, ast.Constant) else "x" for v in node.values)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in parts:
            yield node.lineno, node.value


def _docstrings(tree: ast.AST) -> set[int]:
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                found.add(first.value.lineno)
    return found


def writes_outside_the_store(folder: Path) -> list[str]:
    found = []
    for path in sorted(folder.rglob("*.py")):
        if STORE in path.parents:
            continue
        tree = ast.parse(path.read_text())
        prose = _docstrings(tree)
        found += [f"{path.relative_to(ROOT)}:{line}: {match.group(0)!r}" for line, text in _strings(tree)
                  if line not in prose for match in [WRITES.search(text)] if match]
    return found


@pytest.mark.parametrize("folder", ["harness", "bench"])
def test_no_python_file_outside_the_store_writes_sql(folder):
    assert writes_outside_the_store(ROOT / folder) == []


def test_the_check_finds_a_write_where_there_is_one(tmp_path, monkeypatch):
    module = tmp_path / "harness" / "analysis" / "sneaky.py"
    module.parent.mkdir(parents=True)
    module.write_text('"""Writes: insert into verdicts (a docstring is prose)."""\n'
                      'def f(con, t):\n    con.execute(f"delete from {t} where true")\n'
                      '    con.execute("""create or replace temp view v as select 1""")\n')
    monkeypatch.setattr(f"{__name__}.ROOT", tmp_path)
    monkeypatch.setattr(f"{__name__}.STORE", tmp_path / "harness" / "store")
    assert writes_outside_the_store(tmp_path / "harness") == [
        "harness/analysis/sneaky.py:3: 'delete from'",
        "harness/analysis/sneaky.py:4: 'create or replace temp view'"]


# A read: a select with its from, or a from with its where, order by or group by. A hint that quotes
# a query for the `sql` command (`python -m harness sql "select ..."`) is a message, not a read.
READS = re.compile(r"\bselect\b[\s\S]*\bfrom\b|\bfrom\s+\w+\s+(where|order\s+by|group\s+by)\b", re.I)
HINT = re.compile(r"""harness sql "|e\.g\. "select""")
def reads_outside_the_store(folder: Path) -> dict[str, int]:
    """Python file (relative to ROOT) -> how many of its string literals are SQL that reads."""
    found = {}
    for path in sorted(folder.rglob("*.py")):
        if STORE in path.parents:
            continue
        tree = ast.parse(path.read_text())
        prose = _docstrings(tree)
        count = sum(1 for line, text in _strings(tree) if line not in prose and READS.search(text)
                    and not HINT.search(text))
        if count:
            found[str(path.relative_to(ROOT))] = count
    return found


def test_no_sql_text_outside_the_store_and_sql():
    found = {**reads_outside_the_store(ROOT / "harness"), **reads_outside_the_store(ROOT / "bench")}
    assert found == {}, "a read is a named function of harness/store/ (e.g. campaign_reads.py) or a file of sql/"


def test_the_check_finds_a_read_where_there_is_one(tmp_path, monkeypatch):
    module = tmp_path / "harness" / "campaign" / "sneaky.py"
    module.parent.mkdir(parents=True)
    module.write_text('"""Reads: select * from traces (a docstring is prose)."""\n'
                      'def f(con, t):\n    con.execute(f"select count(*) from {t}")\n'
                      '    con.execute("""with x as (select 1 as a)\n        select a from x""")\n'
                      '    raise ValueError(\'pick one from python -m harness sql "select * from traces"\')\n')
    (tmp_path / "harness" / "store").mkdir()
    (tmp_path / "harness" / "store" / "reads.py").write_text('Q = "select 1 from traces"\n')
    monkeypatch.setattr(f"{__name__}.ROOT", tmp_path)
    monkeypatch.setattr(f"{__name__}.STORE", tmp_path / "harness" / "store")
    assert reads_outside_the_store(tmp_path / "harness") == {"harness/campaign/sneaky.py": 2}

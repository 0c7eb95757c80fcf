"""`campaign --shard I/N` and `merge`: shards 1/3, 2/3, 3/3 merged store what the unsharded
campaign stores (fingerprints, Tables II-IV); merging a store twice, a part missing, or stores of
different campaigns is refused with a message, leaving no store behind."""
import pytest

from harness import store
from harness.cli import main
from harness.fingerprint import fingerprint

CAMPAIGN = ["campaign", "--mutants", "12", "--sut", "genom,bip-a", "--seed", "7", "--jobs", "2"]


@pytest.fixture(scope="module")
def stores(tmp_path_factory):
    folder = tmp_path_factory.mktemp("shards")
    for i in (1, 2, 3):
        assert main([*CAMPAIGN, "--shard", f"{i}/3", "--db", str(folder / f"s{i}.duckdb")]) == 0
    assert main([*CAMPAIGN, "--db", str(folder / "whole.duckdb")]) == 0
    return folder


def _read(db):
    con = store.connect(db, read_only=True)
    try:
        return (fingerprint(con), con.execute("select * from trace_robustness order by sut").fetchall(),
                con.execute("select count(*) from traces").fetchone()[0])
    finally:
        con.close()


@pytest.mark.slow
def test_the_shards_are_disjoint_parts_and_merged_equal_the_whole_campaign(stores):
    counts = [_read(stores / f"s{i}.duckdb")[2] for i in (1, 2, 3)]
    whole = _read(stores / "whole.duckdb")
    assert sum(counts) == whole[2] and all(counts), counts
    assert main(["merge", str(stores / "merged.duckdb"), *(str(stores / f"s{i}.duckdb") for i in (1, 2, 3))]) == 0
    assert _read(stores / "merged.duckdb") == whole


@pytest.mark.slow
def test_a_store_given_twice_or_a_part_missing_is_refused(stores, capsys):
    out = stores / "bad.duckdb"
    assert main(["merge", str(out), *(str(stores / f"s{i}.duckdb") for i in (1, 2, 3, 3))]) == 2
    assert "is given twice" in capsys.readouterr().err
    assert main(["merge", str(out), str(stores / "s1.duckdb"), str(stores / "s2.duckdb")]) == 2
    assert "shard(s) 3/3 missing" in capsys.readouterr().err
    assert main(["merge", str(out), *(str(stores / f"s{i}.duckdb") for i in (1, 2, 3)),
                 "--properties", str(stores / "gone.toml")]) == 2
    err = capsys.readouterr().err
    assert "gone.toml: no such file" in err and "pass --properties FILE" in err
    assert not out.exists()


@pytest.mark.slow
def test_stores_of_different_campaigns_are_refused(stores, tmp_path, capsys):
    other = tmp_path / "other.duckdb"
    argv = [a if a != "7" else "8" for a in CAMPAIGN]
    assert main([*argv, "--shard", "3/3", "--db", str(other)]) == 0
    out = tmp_path / "bad.duckdb"
    assert main(["merge", str(out), str(stores / "s1.duckdb"), str(stores / "s2.duckdb"), str(other)]) == 2
    err = capsys.readouterr().err
    assert "holds another campaign" in err and "seed" in err
    assert main(["merge", str(out), str(stores / "s1.duckdb"), str(stores / "whole.duckdb")]) == 2
    assert "is not the store of one shard of a campaign" in capsys.readouterr().err
    assert not out.exists()


def test_a_bad_shard_option_is_refused(tmp_path, capsys):
    assert main([*CAMPAIGN, "--shard", "4/3", "--db", str(tmp_path / "x.duckdb")]) == 2
    assert "--shard '4/3': give I/N with 1 <= I <= N" in capsys.readouterr().err
    assert not (tmp_path / "x.duckdb").exists()


@pytest.mark.slow
def test_shards_that_shrank_merge_without_their_shrinks(stores, tmp_path, capsys):
    """campaign --shard I/N --shrink stores shrinks beside the shard: merge takes the shard's own traces
    (what the unsharded campaign stores) and says what it left out; the merged store can be shrunk."""
    for i in (1, 2):
        assert main([*CAMPAIGN, "--shard", f"{i}/2", "--shrink", "--db", str(tmp_path / f"s{i}.duckdb")]) == 0
    con = store.connect(tmp_path / "s1.duckdb", read_only=True)
    assert con.execute("select count(*) from shrink_runs").fetchone()[0] > 0
    con.close()
    capsys.readouterr()
    assert main(["merge", str(tmp_path / "merged.duckdb"), str(tmp_path / "s1.duckdb"),
                 str(tmp_path / "s2.duckdb")]) == 0
    assert "left out: the " in capsys.readouterr().out
    assert _read(tmp_path / "merged.duckdb") == _read(stores / "whole.duckdb")
    assert main([*CAMPAIGN, "--shrink", "--db", str(tmp_path / "merged.duckdb")]) == 0  # shrink after merging
    assert "is complete" in capsys.readouterr().out
    con = store.connect(tmp_path / "merged.duckdb", read_only=True)
    assert con.execute("select count(*) from shrink_runs").fetchone()[0] > 0

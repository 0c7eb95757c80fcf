"""A target is a folder: a toy one written here (two modules, three properties, a golden script,
no world) runs, is judged and reported with nothing changed outside its folder."""
import duckdb

from harness.cli import main as cli

INTERFACE = """
[replies]
ok = "T"
stopped = "Z"
not_ready = "R"
refused = "R"
full = "R"
bad = "R"

[modules.pump]
services.Init = { kind = "init" }
services.Run = { kind = "exec", until_stopped = true }
services.Halt = { kind = "exec" }

[modules.valve]
services.Init = { kind = "init" }
services.Open = { kind = "exec" }
services.Halt = { kind = "exec" }
"""

LAYER = """
[layer]
invalid_args = "bad"
no_slot = "full"
stop = "Halt"
default_suts = ["good", "leaky"]

[timing]
Init = { start_s = 0.0, run_s = 0.2 }
Halt = { start_s = 0.0, run_s = 0.05 }
"pump.Run" = { start_s = 0.1, run_s = "forever" }
"valve.Open" = { start_s = 0.1, run_s = 1.0 }

[protections.READY]
kind = "requires_init"
reply = "not_ready"

[protections.HALT]
kind = "interrupts"
reply = "stopped"
stop = true

[protections.DRY]
kind = "rejects_while"
reply = "refused"
while = { "pump.Run" = ["valve.Open"] }

[variants.good]
protections = ["READY", "HALT", "DRY"]

[variants.leaky]
protections = ["READY", "HALT"]
"""

PROPERTIES = """
[[property]]
id = "READY(pump)"
family = "READY"
type = "PC"
x = ["pump.Run", "pump.Halt"]
q = ["pump.Init"]
r_p = "not_ready"

[[property]]
id = "HALT(pump.Run)"
family = "HALT"
type = "EE"
x = ["pump.Run"]
y = ["pump.Halt"]
z_p = "stopped"

[[property]]
id = "DRY(pump.Run)"
family = "DRY"
type = "ES"
x = ["pump.Run"]
y = ["valve.Open"]
r_p = "refused"
"""

GOLDEN = """
send pump.Init as p
send valve.Init as v
wait all
send valve.Open as open
wait open
send pump.Run as run
sleep 2
send pump.Halt as halt
wait all
"""


def test_a_toy_target_folder_runs_end_to_end(tmp_path):
    toy = tmp_path / "toy"
    toy.mkdir()
    for name, text in (("interface.toml", INTERFACE), ("layer.toml", LAYER), ("properties.toml", PROPERTIES),
                       ("golden.mission", GOLDEN)):
        (toy / name).write_text(text)
    db = tmp_path / "toy.duckdb"
    assert cli(["campaign", "--mission", str(toy), "--mutants", "30", "--strategy", "targeted", "--seed", "3",
                "--max-delay", "0", "--jobs", "1", "--db", str(db)]) == 0
    assert cli(["report", "--db", str(db), "--out", str(tmp_path / "report")]) == 0
    con = duckdb.connect(str(db), read_only=True)
    outcomes = con.execute("select sut, count(*), count(*) filter (outcome = 'completed') from traces "
                           "group by sut order by sut").fetchall()
    assert [(sut, n == done) for sut, n, done in outcomes] == [("good", True), ("leaky", True)]
    golden = con.execute("""select t.sut, count(*) filter (verdict in ('FN', 'FP')) from verdicts v
                            join traces t using (trace_id) join scripts s using (script_id)
                            where s.kind = 'golden' group by t.sut order by t.sut""").fetchall()
    assert golden == [("good", 0), ("leaky", 0)]
    rates = dict(((s, f), r) for s, f, r in con.execute("select sut, family, tp_rate from tp_rates").fetchall())
    assert rates[("leaky", "DRY")] == 0.0 and rates[("good", "DRY")] == 1.0  # the protection leaky lacks
    assert "pump.Run" in (tmp_path / "report" / "index.html").read_text()

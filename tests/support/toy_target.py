"""A toy target written by the tests: two modules, three properties, a golden script and a layer
description, small enough to read at once."""

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

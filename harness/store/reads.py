"""Reading whole views in the order the store keeps as data (variants, families, properties)."""
from __future__ import annotations

POSITIONS = {"sut": "variant_positions", "family": "family_positions", "property_id": "property_positions"}


def ordered(con, view: str) -> str:
    """The query of a whole view (or table), its rows in the order of POSITIONS, ties by its columns."""
    columns = [d[0] for d in con.execute(f"select * from {view} limit 0").description]
    ranked = [c for c in POSITIONS if c in columns]
    joins = " ".join(f"left join (select {c}, position as {c}_rank from {POSITIONS[c]}) using ({c})"
                     for c in ranked)
    order = [f"{c}_rank nulls last" for c in ranked] + [str(n) for n in range(1, len(columns) + 1)]
    return f"select v.* from {view} v {joins} order by {', '.join(order)}"


def observed_events(con, trace_id: int) -> list[tuple]:
    """A stored trace's observed events as a Trace holds them (EVENT_COLUMNS order)."""
    return con.execute("select seq, t, kind, rqst_id, module, service, args, reply from events "
                       "where trace_id = ? order by seq", [trace_id]).fetchall()

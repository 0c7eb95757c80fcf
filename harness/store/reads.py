"""Reading whole views in the order the store keeps as data (variants, families, properties), and
facts about the store's history that several commands state."""
from __future__ import annotations

import duckdb

POSITIONS = {"sut": "variant_positions", "family": "family_positions", "property_id": "property_positions"}


def ordered(con, view: str) -> str:
    """The query of a whole view (or table), its rows in the order of POSITIONS, ties by its columns."""
    columns = [d[0] for d in con.execute(f"select * from {view} limit 0").description]
    ranked = [c for c in POSITIONS if c in columns]
    joins = " ".join(f"left join (select {c}, position as {c}_rank from {POSITIONS[c]}) using ({c})"
                     for c in ranked)
    order = [f"{c}_rank nulls last" for c in ranked] + [str(n) for n in range(1, len(columns) + 1)]
    return f"select v.* from {view} v {joins} order by {', '.join(order)}"


def analyses_made(con) -> int:
    """How many analyses judged the store: with fewer than two, there is nothing to compare."""
    try:
        return con.execute("select count(*) from analyses").fetchone()[0]
    except duckdb.CatalogException:  # a store from before analyses were recorded
        return 0

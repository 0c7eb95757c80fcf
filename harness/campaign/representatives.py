"""`campaign --shrink`: shrink the representative trace of every distinct bad behaviour of a
campaign (view bad_behaviours), in worker processes, each failure recorded without stopping the others."""
from __future__ import annotations

import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path
from typing import Iterator

from harness import store
from harness.campaign.shrink import Behaviour, Shrunk, original, shrunk, stored
from harness.errors import UntimelyError
from harness.sut.executive import run_script
from harness.sut.definitions import ExternalSut
from harness.store.record import ShrinkRecord, records
from harness.target.interface import Property


def representatives(con, properties: list[Property], out: Path, external: dict[str, ExternalSut],
                    runner=run_script, jobs: int = 1) -> Iterator[str]:
    """`campaign --shrink`: shrink the representative trace of every distinct bad behaviour
    (view bad_behaviours) not shrunk yet, `jobs` at a time in worker processes; this process
    stores them in the view's order, one line per behaviour. External SUTs run as the campaign's
    arguments define them (`external`), not as the store records them."""
    done = {(s.sut, s.verdict, s.property) for _, _, s in records(con, ShrinkRecord) if s.steps_after is not None}
    mine = {name: sut.config() for name, sut in external.items()}
    todo = [(Behaviour(sut, verdict, property_id), replace(original(con, trace_id), external=mine))
            for sut, property_id, verdict, trace_id in con.execute(
                "select sut, property_id, verdict, representative from bad_behaviours "
                "join variant_positions using (sut) "
                "order by position, verdict = 'hung' desc, verdict, property_id").fetchall()
            if (sut, verdict, property_id) not in done]
    if not todo:
        return
    with ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = [(behaviour, orig, pool.submit(shrunk, orig, behaviour, properties, runner))
                   for behaviour, orig in todo]
        for behaviour, orig, future in futures:
            try:
                result = future.result()
                line = stored(con, behaviour, result, out)
            except Exception as e:  # noqa: BLE001 - one behaviour's failure must not stop the others
                why = str(e) if isinstance(e, UntimelyError) else f"{type(e).__name__}: {e}"
                result = Shrunk(orig, None, 0, 0.0, why)
            if result.error:
                store.record_shrink_failure(con, orig.trace_id, behaviour.sut, behaviour.verdict, behaviour.property_id,
                                            result.error)
                line = f"{behaviour}: not shrunk (table shrink_failures): {result.error}"
            yield line

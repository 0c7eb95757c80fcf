"""The report as a browser shows it: headless chromium renders index.html and a trace page."""
from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from tests.support.report import Page, analysed_store, write_report

CHROMIUM = shutil.which("chromium")
pytestmark = [pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary on PATH; .ci/run installs "
                                                         "Debian's chromium (apt-get install -y chromium)"), pytest.mark.slow]


def _render(page, tmp_path, name: str) -> tuple[Page, bytes]:
    """The DOM chromium built from the page, and a screenshot of it."""
    shot = tmp_path / f"{name}.png"
    done = subprocess.run(
        [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run",
         f"--user-data-dir={tmp_path / ('profile-' + name)}", "--window-size=1300,1000",
         "--dump-dom", f"--screenshot={shot}", page.as_uri()],
        capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return Page(done.stdout), shot.read_bytes()


def test_chromium_renders_the_tables_and_a_timeline(tmp_path):
    out = tmp_path / "report"
    write_report(analysed_store(tmp_path / "store.duckdb"), out, [])
    index, shot = _render(out / "index.html", tmp_path, "index")
    assert shot.startswith(b"\x89PNG") and len(shot) > 10_000
    for table in ("trace_robustness", "table3", "table4", "coverage"):
        assert len(index.tables[table]) > 1, f"table {table} has no rows in the rendered DOM"
    assert len(index.with_class("chart")) == 4

    trace, shot = _render(out / "traces" / "trace-5.html", tmp_path, "trace")
    assert shot.startswith(b"\x89PNG") and len(shot) > 10_000
    assert [lane["data-module"] for lane in trace.with_class("lane")] == ["rflex", "ndd", "antenna"]
    assert len(trace.with_class("bar")) == 6
    assert trace.with_class("world-event")


def test_the_coverage_table_fits_a_1400_pixel_window(tmp_path):
    """Issue 19, item 7: the coverage table (21 columns) ran past the right edge of a 1400 px window."""
    out = tmp_path / "report"
    write_report(analysed_store(tmp_path / "store.duckdb"), out, [])
    probe = ("<script>document.addEventListener('DOMContentLoaded', () => { const t = document.getElementById("
             "'coverage'); document.body.setAttribute('data-fit', [t.getBoundingClientRect().right, "
             "document.documentElement.clientWidth, t.rows[0].cells.length].join(' ')); });</script></body>")
    page = out / "probe.html"
    page.write_text((out / "index.html").read_text().replace("</body>", probe))
    done = subprocess.run(
        [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
         f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1400,1000", "--dump-dom", page.as_uri()],
        capture_output=True, text=True, timeout=120)
    right, visible, columns = (float(v) for v in re.search(r'data-fit="([^"]+)"', done.stdout)[1].split())
    assert columns >= 17 and right <= visible, (right, visible)

"""bench/run_all.py's table (not its timings): ratios run the right way, a script that fails
or writes no figures gives rows saying why, and the outputs state the machine."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "bench"
sys.path.insert(0, str(BENCH))

import run_all  # noqa: E402
import table_output  # noqa: E402
import table_rows  # noqa: E402
from table_rows import Row  # noqa: E402

MACHINE = {"cores": 2, "blas": "openblas-openmp/libblas.so.3", "threads": 2,
           "threads_from": "os.cpu_count()", "python": "3.11", "numpy": "1.26", "bpy": "4.5",
           "load_average": [0.5, 0.5, 0.5]}


def test_ratio_is_times_better_whichever_way_the_unit_runs():
    assert Row("rate", "M tets/s", ours=40.0, peer=10.0).ratio == 4.0
    assert Row("time", "s", ours=2.0, peer=10.0, higher_is_better=False).ratio == 5.0
    assert Row("no peer", "s", ours=2.0).ratio is None
    assert Row("failed", "s", peer=3.0).ratio is None


def test_stitch_rows_hold_figures_to_the_issue_targets():
    figures = {"tets": 4_873_728, "stitch_mtets_per_s": 60.0, "stitch_first_mtets_per_s": 20.0,
               "stitch_core_mtets_per_s": 70.0, "output_copy_mtets_per_s": 250.0, "stitch_peak_over_output": 1.7,
               "stitch_peak_bytes": 170 * 2**20, "output_bytes": 100 * 2**20, "slice_ms_per_frame": 19.0,
               "memory_bound_slice_ms": 2.0, "slice_frames_per_s": 52.6, "faces_per_frame": 340_000, "index_s": 0.4,
               "package_slice_ms_per_frame": 25.0, "package_faces_per_frame": 85_000, "package_prism_frames": True}
    best, first, peak, frame, package = table_rows.stitch_rows(figures)
    assert (best.met, first.met, peak.met, frame.met, package.met) == (True, False, False, True, False)
    assert best.ratio == pytest.approx(60.0 / 250.0)
    assert frame.ratio == pytest.approx(2.0 / 19.0)
    assert package.ratio == pytest.approx(19.0 / 25.0) and "prism frame" in package.note and "85,000" in package.note


def stand_in(tmp_path: Path, body: str) -> run_all.Job:
    script = tmp_path / "bench_stand_in.py"
    script.write_text("import argparse, json, sys\n"
                      "p = argparse.ArgumentParser(); p.add_argument('--json'); a = p.parse_args()\n" + body)
    return run_all.Job("stand_in", str(script), [], lambda f: [Row("measure", "s", ours=f["seconds"])],
                       ["stand-in measure"])


@pytest.fixture
def out(tmp_path: Path) -> Path:
    for folder in ("figures", "logs"):
        (tmp_path / "out" / folder).mkdir(parents=True)
    return tmp_path / "out"


def test_figures_of_a_script_become_its_rows(tmp_path, out):
    job = stand_in(tmp_path, "json.dump({'seconds': 1.5}, open(a.json, 'w'))\n")
    rows, run = run_all.run_job(job, out, dict(os.environ), full=False)
    assert [(r.measure, r.ours) for r in rows] == [("measure", 1.5)]
    assert run["status"] == 0


def test_a_failing_script_gives_a_row_saying_why(tmp_path, out):
    job = stand_in(tmp_path, "print('OpenVDB is not built', file=sys.stderr); sys.exit(3)\n")
    rows, run = run_all.run_job(job, out, dict(os.environ), full=False)
    assert len(rows) == 1 and rows[0].measure == "stand-in measure" and rows[0].ours is None
    assert "exited with 3" in rows[0].note and "OpenVDB is not built" in rows[0].note
    assert "OpenVDB is not built" in Path(run["log"]).read_text()


def test_figures_missing_a_measure_give_a_row_saying_which(tmp_path, out):
    job = stand_in(tmp_path, "json.dump({'other': 1}, open(a.json, 'w'))\n")
    rows, _ = run_all.run_job(job, out, dict(os.environ), full=False)
    assert rows[0].ours is None and "'seconds'" in rows[0].note


def test_table_json_and_chart_state_the_machine(tmp_path):
    rows = [Row("stitch", "M tets/s", 40.0, 250.0, "numpy copy", target=">= 50", met=False),
            Row("refine", "splits/s", 5e4, note="no peer")]
    text = table_output.format_table(rows, MACHINE)
    assert text.splitlines()[0].startswith("machine: cores 2; threads 2") and "openblas-openmp" in text
    table_output.write_json(tmp_path / "table.json", rows, MACHINE, {})
    written = json.loads((tmp_path / "table.json").read_text())
    assert written["machine"]["blas"] == MACHINE["blas"]
    assert written["rows"][0]["ratio"] == pytest.approx(0.16) and written["rows"][1]["ratio"] is None
    pytest.importorskip("matplotlib", reason="the chart needs matplotlib (scripts/install-deps.sh installs it)")
    table_output.write_chart(tmp_path / "table.png", rows, MACHINE)
    assert (tmp_path / "table.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

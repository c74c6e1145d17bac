"""The scaling benchmark's bookkeeping (bench/derivation_report.py, bench/scaling_report.py).

No timing is judged here; these check that a run past its limit is killed and reported as a
timeout, that medians count timeouts as infinitely long, and that the growth fit recovers a
known power law.
"""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parent.parent / "bench"
sys.path.insert(0, str(BENCH))

import scaling_report as report  # noqa: E402 - the bench folder is not a package
from derivation_scaling import run_process, symkin_command  # noqa: E402
from scaling_children import RUSAGE_TAG  # noqa: E402


def test_growth_fit_recovers_a_power_law():
    # t = 0.01 n^3 by hand: the log-log slope is exactly 3.
    points = [(n, 0.01 * n**3) for n in (2, 4, 6, 8)]
    assert report.growth_exponent(points) == "n^3.0"
    # A timeout (inf) or a missing value is left out of the fit, not counted as data.
    assert report.growth_exponent([*points, (12, math.inf), (10, None)]) == "n^3.0"
    assert report.growth_exponent(points[:2]) == "—"


def _results(*samples: report.Sample) -> tuple[report.Results, tuple]:
    results = report.Results()
    key = ("generic/numeric", 6, "tau")
    results.samples[key] = list(samples)
    return results, key


def test_median_counts_a_timeout_as_longer_than_any_run():
    done = [report.Sample(result={"seconds": s}) for s in (1.0, 3.0)]
    late = report.Sample(timeout=300)
    results, key = _results(*done, late)
    assert report.cell(results, key) == "3.000 (1 of 3 timed out)"
    results, key = _results(done[0], late, late)
    assert report.cell(results, key) == "> 300 s (timeout)"


def test_ratio_is_peer_over_symkin_and_a_bound_after_a_peer_timeout():
    results = report.Results()
    ours, theirs = ("g", 6, "tau"), ("g", 6, "sb-tau")
    results.samples[ours] = [report.Sample(result={"seconds": 2.0})]
    results.samples[theirs] = [report.Sample(result={"seconds": 5.0})]
    assert report.ratio(results, theirs, ours) == "2.50×"
    results.samples[theirs] = [report.Sample(timeout=300)]
    assert report.ratio(results, theirs, ours) == "> 150.0×"


def test_a_process_past_its_cpu_limit_is_killed_and_reported_as_a_timeout():
    spin = [sys.executable, "-c", "while True: pass"]
    sample = run_process(spin, 0.3, dict(os.environ))
    assert sample.timeout == 0.3
    assert sample.cpu is not None and sample.cpu >= 0.3


def test_a_finished_process_gives_its_json_cpu_time_and_peak_memory():
    # 50 MB held at once: the child's peak RSS must show at least that.
    script = "import json; b = bytearray(50 * 2**20); print(json.dumps({'seconds': 1.5}))"
    sample = run_process([sys.executable, "-c", script], 60, dict(os.environ))
    assert sample.timeout is None and sample.error is None
    assert sample.result == {"seconds": 1.5}
    assert sample.rss_mb is not None and sample.rss_mb > 50


@pytest.mark.slow  # imports symkin in a fresh process: seconds on a loaded machine
def test_the_symkin_wrapper_runs_the_command_and_reports_its_own_cpu_time():
    sample = run_process([*symkin_command(), "list"], 60, dict(os.environ))
    assert sample.error is None and sample.timeout is None
    (line,) = [x for x in sample.stderr.splitlines() if x.startswith(RUSAGE_TAG)]
    figures = json.loads(line.removeprefix(RUSAGE_TAG))
    # Importing symkin alone costs CPU; `symkin list` compiles nothing.
    assert figures["own_cpu"] > 0 and figures["compiler_cpu"] == 0
    assert sample.cpu is not None and sample.cpu >= figures["own_cpu"] - 0.05


# The shape of ``symkin derive --verbose`` (nested phases end, and print, before their parent).
VERBOSE = """symkin: deriving planar_3r and emitting numpy, c ...
symkin:         0.22 s  the link transforms and forward kinematics
symkin:         0.03 s  the link transforms and forward kinematics
symkin:         1.00 s  the Newton-Euler equations of motion
symkin:       1.99 s  the kernels (CSE and rewrite passes)
symkin:     2.12 s  the numpy files
symkin:     0.36 s  the c files
symkin: cache: stored /tmp/x/symkin/derive-ef09.json
wrote 11 files to /tmp/sc/:
"""


def test_verbose_phases_split_into_outermost_and_nested():
    outer, nested = report.phases_of(VERBOSE)
    assert outer == {"the numpy files": 2.12, "the c files": 0.36}
    assert nested == {
        "the link transforms and forward kinematics": pytest.approx(0.25),
        "the Newton-Euler equations of motion": 1.0,
        "the kernels (CSE and rewrite passes)": 1.99,
    }
    assert report.phases_of("wrote 11 files\n") == ({}, {})

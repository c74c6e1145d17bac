"""The benchmarks' bookkeeping (bench/derivation_time.py, bench/derivation_whole.py).

No timing is judged here: these check that the peak memory a child reports is its own (not the
parent's, which Linux carries through ``exec`` into ``ru_maxrss``), that the contenders
alternate round by round and a timed-out one is not run again, and that the tables state
their ratios as symkin over the peer and say "not run" for a peer without a checkout.
"""

from __future__ import annotations

import os
import subprocess
import sys
from argparse import Namespace
from pathlib import Path

BENCH = Path(__file__).resolve().parent.parent / "bench"
sys.path.insert(0, str(BENCH))

import derivation_time  # noqa: E402 - the bench folder is not a package
import derivation_whole  # noqa: E402
from scaling_report import Sample  # noqa: E402

REPORT = (
    f"import sys; sys.path.insert(0, {str(BENCH)!r}); import resource; "
    "from derivation_time import peak_rss_mb; "
    "print(peak_rss_mb(), resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)"
)


def test_a_child_reports_its_own_peak_memory_not_its_parents():
    # The parent holds 300 MB (touched, so resident) while it starts the child.
    ballast = bytearray(300 * 2**20)
    ballast[::4096] = b"x" * len(range(0, len(ballast), 4096))
    out = subprocess.run(
        [sys.executable, "-c", REPORT], capture_output=True, text=True, check=True
    ).stdout
    own, inherited = (float(x) for x in out.split())
    del ballast
    assert own < 150  # a bare interpreter and the bench module: tens of MB
    # What the fix is for: ru_maxrss of the same child includes the parent's peak.
    assert inherited > 300


def test_the_peak_memory_counts_what_the_child_itself_holds():
    script = f"b = bytearray(200 * 2**20); b[::4096] = b'x' * len(range(0, len(b), 4096)); {REPORT}"
    out = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, check=True
    ).stdout
    own, _ = (float(x) for x in out.split())
    assert own > 200


def test_contenders_alternate_round_by_round_and_a_timeout_is_not_rerun(monkeypatch):
    calls = []

    def fake_run_child(kind, name, timeout):
        calls.append((kind, name))
        if kind == "rtb" and sum(1 for c in calls if c[0] == "rtb") == 2:
            return {"timeout": timeout}
        return {"seconds": 1.0, "fk_jac_s": 1.0, "rss_mb": 10.0}

    monkeypatch.setattr(derivation_time, "run_child", fake_run_child)
    jobs = [("symkin", "puma560", 5.0), ("rtb", "Puma560", 7.0)]
    runs = derivation_time.alternate(jobs, 3)
    assert calls == [
        ("symkin", "puma560"),
        ("rtb", "Puma560"),
        ("symkin", "puma560"),
        ("rtb", "Puma560"),  # times out: not run in round 3
        ("symkin", "puma560"),
    ]
    assert len(runs["symkin", "puma560"].results) == 3
    assert runs["rtb", "Puma560"].timeout == 7.0


def _runs(*results):
    runs = derivation_time.Runs()
    runs.results.extend(results)
    return runs


def test_the_like_with_like_ratio_is_symkins_derivation_and_cse_over_the_peers():
    # symkin 0.2 + 0.1 s, RTB 0.1 + 0.5 s: symkin takes half as long, ratio 0.50.
    ours = _runs(
        {
            "dof": 6,
            "fk_jac_s": 0.2,
            "cse_s": 0.1,
            "ops": 500,
            "cse_ops": 150,
            "rss_mb": 100.0,
            "det_s": 1.0,
        }
    )
    peer = _runs(
        {
            "seconds": 0.1,
            "cse_s": 0.5,
            "ops": 7000,
            "cse_ops": 400,
            "rss_mb": 170.0,
            "disagreement": 1e-16,
        }
    )
    args = Namespace(repeat=1, peer_timeout=300.0)
    text = derivation_time.render({"puma560": ours}, {"puma560": peer}, args, (1.0, 2.0))
    (row,) = [line for line in text.splitlines() if "`fkine` + `jacob0`" in line]
    assert row.rstrip().endswith("| 0.50 |")
    (own,) = [line for line in text.splitlines() if line.startswith("| puma560 | 6 |")]
    assert own.rstrip().endswith("| 100 |")  # the peak RSS column
    assert "Load average (1 min) at the start and end of the run: 1.0 and 2.0" in text


def _sample(cpu, wall, rss):
    return Sample(wall=wall, cpu=cpu, rss_mb=999.0, result={"rss_mb": rss})


def test_the_whole_command_table_gives_symkin_over_each_peer_and_says_not_run():
    samples = {
        "symkin": [_sample(8.0, 16.0, 150.0), _sample(10.0, 20.0, 150.0)],
        "symkin-no-build": [_sample(7.0, 14.0, 150.0)],
        "rtb": [_sample(4.5, 5.0, 180.0)],
    }
    lines = derivation_whole.render_whole(samples, None)
    (rtb,) = [line for line in lines if line.startswith("| RTB")]
    assert rtb.endswith("| 2.00 |")  # median 9 s over 4.5 s
    assert "| 180 |" in rtb  # the process's own peak, not wait4's 999 MB
    (sympybotics,) = [line for line in lines if line.startswith("| SymPyBotics")]
    assert "not run (no `--sympybotics DIR`)" in sympybotics
    (regressor,) = [line for line in lines if "--regressor" in line]
    assert "| not run |" in regressor and "--sympybotics" not in regressor


def test_the_sympybotics_flag_rejects_a_folder_without_the_package(tmp_path):
    done = subprocess.run(
        [sys.executable, str(BENCH / "derivation_time.py"), "--sympybotics", str(tmp_path)],
        capture_output=True,
        text=True,
        env=dict(os.environ),
    )
    assert done.returncode == 2
    assert "no sympybotics package in it" in done.stderr
    assert "Traceback" not in done.stderr

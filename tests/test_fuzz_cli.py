"""Fuzzing the ``symkin`` command line in real subprocesses, plus one regression test per finding.

The Hypothesis suites (``fuzz_cases.SUITES``) draw a fixed, derandomized set of cases each: small
valid robots mutated with hostile numbers, expressions, names and texts, and hostile
command-line arguments.  Every case must be ``clean`` (see ``fuzz_cases``): a well-formed result
or one ``symkin: error:`` line with exit status 2; never a traceback, a hang, malformed JSON,
raw control characters, generated C that fails ``-Werror -pedantic``, a generated module that
does not import, or LaTeX where the title escapes into live TeX.  A failing suite lists every
non-clean case, grouped, with its arguments, file and standard-error tail.  The counts per
category are printed at the end of the module (``-s`` is not needed).

The regression tests below pin the reproductions found while writing the fuzzer; each accepts a
clean rejection (exit 2, one error line) or the correct result.
"""

from __future__ import annotations

import importlib.util
import json
import math
import subprocess
import time
from collections import Counter
from collections.abc import Iterator, Sequence
from pathlib import Path

import pytest

import fuzz_cases as fz
from fuzz_cases import Case, Outcome, run_case, run_cases, toml_string

pytestmark = pytest.mark.slow

TALLY: dict[str, Counter[str]] = {}
REJECTED: dict[str, int] = {}


@pytest.fixture(scope="module", autouse=True)
def print_tally(request: pytest.FixtureRequest) -> Iterator[None]:
    """After the module: counts per category of every generated case, past output capture."""
    start = time.monotonic()
    yield
    if not TALLY:
        return
    total: Counter[str] = Counter()
    lines = ["", "symkin CLI fuzz: counts per category (rejected = clean exit 2)"]
    for suite, counts in TALLY.items():
        total.update(counts)
        lines.append(f"  {fz.format_tally(counts, suite)}, rejected {REJECTED[suite]}")
    lines.append(f"  {fz.format_tally(total, 'all suites')}, rejected {sum(REJECTED.values())}")
    lines.append(f"  module time {time.monotonic() - start:.0f} s, {fz.JOBS} jobs")
    reporter = request.config.pluginmanager.get_plugin("terminalreporter")
    capture = request.config.pluginmanager.get_plugin("capturemanager")
    if reporter is None or capture is None:
        print("\n".join(lines))
        return
    with capture.global_and_fixture_disabled():
        for line in lines:
            reporter.write_line(line)


# ---------------------------------------------------------------------------------------------
# The Hypothesis suites
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("suite", list(fz.SUITES))
def test_fuzz_suite(suite: str) -> None:
    outcomes = fz.run_suite(suite)
    TALLY[suite] = fz.tally(outcomes)
    REJECTED[suite] = sum(o.clean and o.returncode == 2 for o in outcomes)
    if not all(o.clean for o in outcomes):
        pytest.fail(fz.failure_report(outcomes), pytrace=False)


# ---------------------------------------------------------------------------------------------
# The classifier itself (no subprocess)
# ---------------------------------------------------------------------------------------------


def classify(
    argv: Sequence[str], code: int, out: str = "", err: str = "", tmp: Path | None = None
) -> str:
    files = (("robot.toml", 'title = "\\\\input{/etc/hostname}"\n'),)
    return fz._classify(list(argv), files, code, out, err, tmp or Path("/nonexistent"), set())[0]


def test_classifier() -> None:
    assert classify(["eval", "--json"], 0, '{"det": 1.0}') == "clean"
    assert classify(["eval", "--json"], 0, '{"det": NaN}') == "wrong"
    assert classify(["eval", "--json"], 0, '{"det": -Infinity}') == "wrong"
    assert classify(["eval", "--json"], 0, '{"det": ') == "wrong"
    assert classify(["show"], 0, "ok\tfine\n", "symkin: warning: w\n") == "clean"
    assert classify(["show"], 0, "a\x00b") == "wrong"
    assert classify(["show"], 0, "a\u202eb") == "wrong"
    assert classify(["show"], 0, "", "RuntimeWarning: overflow\n") == "wrong"
    assert classify(["show"], 2, "", "symkin: error: bad\n") == "clean"
    assert classify(["derive"], 2, "", "symkin: deriving x ...\nsymkin: error: bad\n") == "clean"
    assert classify(["show"], 2, "", "symkin: error: bad\nsecond line\n") == "wrong"
    assert classify(["show"], 2, "", "symkin: error: a\nsymkin: error: b\n") == "wrong"
    usage = "usage: symkin eval [-h]\n              ROBOT\nsymkin eval: error: required\n"
    assert classify(["eval"], 2, "", usage) == "clean"
    assert classify(["show"], 1) == "traceback"
    assert classify(["ik"], 1) == "clean"
    assert classify(["show"], 3, "", "symkin: internal error: x\n") == "traceback"
    assert classify(["show"], -11) == "traceback"
    assert classify(["show"], 2, "", "Traceback (most recent call last):\n") == "traceback"


def test_classifier_tex(tmp_path: Path) -> None:
    tex = tmp_path / "x.tex"
    tex.write_text("% title: \\input{/etc/hostname}\n\\title{\\textbackslash{}input}\n")
    assert classify(["latex"], 0, tmp=tmp_path) == "clean"
    tex.write_text("% title: x\n\\input{/etc/hostname}\n")
    assert classify(["latex"], 0, tmp=tmp_path) == "wrong"
    tex.write_text("\\title{50\\% \\input{/etc/hostname}}\n")
    assert classify(["latex"], 0, tmp=tmp_path) == "wrong"
    assert fz.live_tex("a \\% b % c") == "a \\% b "


# ---------------------------------------------------------------------------------------------
# Helpers of the regression tests
# ---------------------------------------------------------------------------------------------

ROBOT = fz.ROBOT


def robot_text(
    joints: str = 'type = "revolute"\na = "L1"',
    *,
    name: str = "arm",
    title: str | None = None,
    source: str | None = None,
    parameters: str = "L1 = 0.5",
    count: int = 1,
) -> str:
    """A robot file: ``count`` copies of the joint table ``joints``, with optional texts."""
    head = [f"name = {toml_string(name)}"]
    if title is not None:
        head.append(f"title = {toml_string(title)}")
    if source is not None:
        head.append(f"source = {toml_string(source)}")
    body = "".join(f"\n[[joints]]\n{joints}\n" for _ in range(count))
    return "\n".join(head) + f"\n\n[parameters]\n{parameters}\n" + body


LINK = (
    '[joints.link]\nmass = 1.0\ncom = ["-L1/2", 0, 0]\n'
    "inertia = { ixx = 0.01, iyy = 0.02, izz = 0.02 }"
)
DYNAMIC_JOINT = f'type = "revolute"\na = "L1"\n{LINK}'


def derive_argv(emit: str = "numpy,c") -> tuple[str, ...]:
    return ("derive", ROBOT, "--out", "{tmp}/out", "--emit", emit, "--no-build")


def assert_clean(outcomes: Sequence[Outcome]) -> None:
    bad = [o for o in outcomes if not o.clean]
    if bad:
        pytest.fail("\n\n".join(o.report() for o in bad), pytrace=False)


def run_each(text: str, *argvs: Sequence[str]) -> list[Outcome]:
    """Run several commands on one robot file concurrently."""
    cases = []
    for argv in argvs:
        timeout = fz.DERIVE_TIMEOUT if argv[0] in ("derive", "latex") else fz.QUICK_TIMEOUT
        cases.append(Case(tuple(argv), (("robot.toml", text),), timeout, "regression"))
    return run_cases(cases)


def load_module(path: Path) -> object:
    spec = importlib.util.spec_from_file_location(f"fuzz_regression_{path.stem}", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def json_of(outcome: Outcome) -> dict:
    return json.loads(outcome.stdout)


# ---------------------------------------------------------------------------------------------
# Regression tests, one per finding
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("key", "text"),
    [
        ("title", "x\n\\input{/etc/hostname}"),
        ("title", "\\input{/etc/hostname}"),
        ("title", "}\\AtBeginDocument{\\input{/etc/hostname}}{"),
        ("source", "%\n\\immediate\\openout1=pwned.tex"),
        ("source", "^^5cinput{/etc/hostname}"),
    ],
)
def test_tex_injection_through_title(key: str, text: str) -> None:
    """The title and source must stay text (or be rejected), never live TeX in the document."""
    robot = robot_text(**{key: text})
    assert_clean(run_each(robot, ("latex", ROBOT, "-o", "{tmp}/doc/x.tex"), derive_argv("latex")))


@pytest.mark.needs_latex
def test_tex_injection_through_title_pdf() -> None:
    robot = robot_text(title="x\n\\input{/etc/hostname}")
    outcome = run_case(("latex", ROBOT, "-o", "{tmp}/x.tex", "--pdf"), {"robot.toml": robot}, 120)
    assert_clean([outcome])
    if outcome.returncode == 0:
        assert Path("/etc/hostname").read_text().strip() not in outcome.stdout


def test_parameter_named_M_mass_matrix() -> None:
    """One revolute joint, link with mass 2, COM on the axis (a = d = 0), only izz = M = 0.7.

    The link spins about its own z axis, which is the joint axis z0, so its kinetic energy is
    izz dq^2 / 2 (the COM does not move) and M(q) = [[izz]] = [[0.7]] for every q.
    """
    robot = robot_text(
        'type = "revolute"\n[joints.link]\nmass = 2.0\ninertia = { izz = "M" }',
        parameters="M = 0.7",
    )
    (outcome,) = run_each(robot, ("eval", ROBOT, "--q", "0.3", "--dynamics", "--json"))
    assert_clean([outcome])
    if outcome.returncode == 0:
        assert json_of(outcome)["M"] == [[pytest.approx(0.7, abs=1e-12)]], outcome.report()


def test_parameter_named_mu() -> None:
    """``mu`` names the manipulability output in generated code: 2R arm with a1 = a2 = mu = 0.3.

    The C must compile and the NumPy manipulability (rows x, y) must be |a1 a2 sin q2|.
    """
    robot = robot_text('type = "revolute"\na = "mu"', parameters="mu = 0.3", count=2)

    def manipulability(folder: Path) -> float | None:
        path = folder / "out" / "numpy" / "arm_kinematics.py"
        if not path.exists():
            return None
        return float(load_module(path).manipulability([0.1, 0.2], [0.3]))

    outcome = run_case(derive_argv(), {"robot.toml": robot}, 45, inspect=manipulability)
    assert_clean([outcome])
    if outcome.returncode == 0:
        expected = 0.3 * 0.3 * math.sin(0.2)
        assert outcome.extra["inspect"] == pytest.approx(expected, rel=1e-12), outcome.report()


@pytest.mark.parametrize(
    "title",
    ["a\x00b", "\u202eevil\u202c", "\x1b[31mred\x1b[0m", "\u2066x\u2069"],
    ids=["nul", "bidi-rlo", "ansi", "bidi-isolate"],
)
def test_control_characters_in_title(title: str) -> None:
    """NUL, ANSI escapes and bidi controls in the title never reach output or generated files."""
    robot = robot_text(DYNAMIC_JOINT, title=title, source=title)
    assert_clean(
        run_each(
            robot,
            ("show", ROBOT),
            ("eval", ROBOT, "--q", "0.3", "--json"),
            derive_argv("numpy,c,python"),
            ("latex", ROBOT, "-o", "{tmp}/x.tex"),
        )
    )


@pytest.mark.parametrize(
    "title", ["*/ int x = 1; /*", '""" import os """', "back\\slash\\", "a */ b \\\n c"]
)
def test_comment_terminators_in_title_compile(title: str) -> None:
    """A title with ``*/``, triple quotes or backslashes: generated C compiles with -Werror
    -pedantic and the NumPy and CasADi modules import (checked by the runner)."""
    robot = robot_text(DYNAMIC_JOINT, title=title, source=title)
    assert_clean(run_each(robot, derive_argv("numpy,c,python,casadi")))


def test_thirty_digit_integer() -> None:
    robot = robot_text('type = "revolute"\na = 123456789012345678901234567890\n' + LINK, count=2)
    assert_clean(
        run_each(
            robot,
            ("show", ROBOT),
            ("eval", ROBOT, "--q", "0.3,0.2", "--json"),
            ("eval", ROBOT, "--q", "0.3,0.2", "--dq", "1,1", "--json", "--dynamics"),
            derive_argv(),
        )
    )


def test_float_precision_with_huge_parameter() -> None:
    """A parameter value beyond float range (1e300) with ``--precision float``: the C example
    must still compile with -Werror (or the combination is refused)."""
    robot = robot_text(DYNAMIC_JOINT, parameters="L1 = 0.5\nL2 = 1e300")
    robot = robot.replace('a = "L1"', 'a = "L1"\nd = "L2"')
    assert_clean(run_each(robot, (*derive_argv("c"), "--precision", "float")))


def test_underflowing_constant_in_c() -> None:
    """gravity = 1e-300*1e-300 (1e-600) put into the C code as a literal: -Werror=overflow
    ("floating constant truncated to zero"), found by the derive suite."""
    robot = robot_text(DYNAMIC_JOINT, count=2)
    robot = robot.replace('name = "arm"', 'name = "arm"\ngravity = [0, "1e-300*1e-300", -9.81]')
    assert_clean(run_each(robot, derive_argv(), (*derive_argv(), "--numeric-parameters")))


def test_eval_json_overflow_gives_no_nan() -> None:
    """a = 1e300 is allowed, but det J = a1 a2 sin q2 overflows: no Infinity/NaN in the JSON."""
    robot = robot_text('type = "revolute"\na = 1e300', count=2)
    assert_clean(run_each(robot, ("eval", ROBOT, "--q", "0.1,0.2", "--json")))


@pytest.mark.parametrize("expression", ["L1**L1", "L1**(L1**L1)", "(L1**L1)**L1"])
def test_power_towers(expression: str) -> None:
    joint = f'type = "revolute"\na = "{expression}"\nd = "{expression}"\n{LINK}'
    robot = robot_text(joint, count=2)
    assert_clean(
        run_each(
            robot,
            ("show", ROBOT),
            ("eval", ROBOT, "--q", "0.3,0.2", "--dq", "1,1", "--json", "--dynamics"),
            derive_argv(),
        )
    )


@pytest.mark.parametrize("expression", ["1/(2*L1 - 1)", "(2*L1 - 1)**-2", "L1/(1 - 2*L1)"])
def test_pole_at_parameter_default(expression: str) -> None:
    """L1 = 0.5 puts the expression on its pole: reject it or evaluate it finitely."""
    joint = f'type = "revolute"\na = "{expression}"\n{LINK}'
    robot = robot_text(joint, count=2)
    assert_clean(
        run_each(
            robot,
            ("show", ROBOT),
            ("eval", ROBOT, "--q", "0.3,0.2", "--json"),
            ("eval", ROBOT, "--q", "0.3,0.2", "--dq", "1,1", "--json", "--dynamics"),
            derive_argv(),
        )
    )


def test_pole_reached_with_set() -> None:
    """The default L1 = 0.3 is fine; ``--set L1=0.5`` moves onto the pole."""
    joint = f'type = "revolute"\na = "1/(2*L1 - 1)"\n{LINK}'
    robot = robot_text(joint, parameters="L1 = 0.3", count=2)
    assert_clean(
        run_each(
            robot,
            ("eval", ROBOT, "--q", "0.3,0.2", "--set", "L1=0.5", "--json"),
            (
                "eval",
                ROBOT,
                "--q",
                "0.3,0.2",
                "--dq",
                "1,1",
                "--set",
                "L1=0.5",
                "--json",
                "--dynamics",
            ),
        )
    )


def test_huge_joint_velocity() -> None:
    robot = robot_text(DYNAMIC_JOINT, count=2)
    assert_clean(
        run_each(
            robot,
            ("eval", ROBOT, "--q", "0.1,0.2", "--dq", "1e308,1e308", "--json", "--dynamics"),
            (
                "eval",
                ROBOT,
                "--q",
                "0.1,0.2",
                "--dq",
                "1e308,1",
                "--ddq",
                "1e308,1e308",
                "--json",
                "--dynamics",
            ),
            (
                "eval",
                ROBOT,
                "--q",
                "0.1,0.2",
                "--dq",
                "1e308,1e308",
                "--point",
                "2:0.1,0,0",
                "--json",
            ),
        )
    )


def test_ik_negative_seed() -> None:
    (outcome,) = run_each(
        robot_text(count=2), ("ik", ROBOT, "--target", "5,5", "--seed", "-1", "--restarts", "2")
    )
    assert_clean([outcome])


def test_show_dev_zero_exits_quickly() -> None:
    """An endless file must be refused with exit 2 (not read into memory until the cap)."""
    outcome = run_case(("show", "/dev/zero"), (), 20)
    assert_clean([outcome])
    assert outcome.returncode == 2, outcome.report()


@pytest.mark.parametrize("planted", ["file", "folder"])
def test_derive_does_not_write_through_symlink(planted: str, tmp_path: Path) -> None:
    """``out/c/arm.c`` (or ``out/c``) is a symlink to a user's file (folder) outside --out."""
    outside = tmp_path / "outside"
    outside.mkdir()
    user_file = outside / "arm.c"
    user_file.write_text("/* the user's own file */\n")

    def plant(folder: Path) -> None:
        (folder / "out").mkdir()
        if planted == "file":
            (folder / "out" / "c").mkdir()
            (folder / "out" / "c" / "arm.c").symlink_to(user_file)
        else:
            (folder / "out" / "c").symlink_to(outside, target_is_directory=True)

    outcome = run_case(derive_argv("numpy,c"), {"robot.toml": robot_text()}, 45, setup=plant)
    assert user_file.read_text() == "/* the user's own file */\n", outcome.report()
    assert_clean([outcome])


# ---------------------------------------------------------------------------------------------
# generate --root with a symlinked robot folder and a user file (about 75 s; started early)
# ---------------------------------------------------------------------------------------------

NOTES = "my notes, not generated\n"


@pytest.fixture(scope="module", autouse=True)
def generate_process(
    request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[dict | None]:
    """Start ``symkin generate --root DIR`` when the module starts (if a generate test is
    selected), so that it overlaps the other tests: DIR/ur5 -> OUTSIDE holding notes.txt, and
    a real DIR/scara/ holding notes.txt."""
    if not any(item.name.startswith("test_generate_") for item in request.session.items):
        yield None
        return
    base = tmp_path_factory.mktemp("generate")
    root, outside = base / "root", base / "outside"
    root.mkdir()
    outside.mkdir()
    (outside / "notes.txt").write_text(NOTES)
    (root / "ur5").symlink_to(outside, target_is_directory=True)
    (root / "scara").mkdir()
    (root / "scara" / "notes.txt").write_text(NOTES)
    command = [*fz._limit_prefix(), *fz.symkin_command(), "generate", "--root", str(root)]
    process = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=fz._environment(),
        start_new_session=True,
    )
    state = {"process": process, "root": root, "outside": outside, "start": time.monotonic()}
    yield state
    if process.poll() is None:
        fz._kill(process)
        process.communicate()


@pytest.fixture
def generate_run(generate_process: dict | None) -> dict:
    """The finished generate run: exit status, output, folders and seconds."""
    assert generate_process is not None
    if "code" not in generate_process:
        process = generate_process["process"]
        try:
            out, err = process.communicate(timeout=600)
        except subprocess.TimeoutExpired:
            fz._kill(process)
            out, err = process.communicate()
        generate_process.update(
            code=process.returncode,
            stdout=out,
            stderr=err,
            seconds=time.monotonic() - generate_process["start"],
        )
    return generate_process


def _generate_report(run: dict) -> str:
    tail = "\n".join(run["stderr"].splitlines()[-8:])
    return f"exit {run['code']} after {run['seconds']:.0f} s; stderr tail:\n{tail}"


@pytest.mark.slow
def test_generate_keeps_symlinked_folder(generate_run: dict) -> None:
    outside = generate_run["outside"]
    assert outside.is_dir(), _generate_report(generate_run)
    assert (outside / "notes.txt").exists(), _generate_report(generate_run)
    assert (outside / "notes.txt").read_text() == NOTES, _generate_report(generate_run)
    assert "Traceback" not in generate_run["stderr"], _generate_report(generate_run)
    assert generate_run["code"] in (0, 2), _generate_report(generate_run)


@pytest.mark.slow
def test_generate_keeps_user_file(generate_run: dict) -> None:
    notes = generate_run["root"] / "scara" / "notes.txt"
    assert notes.exists(), _generate_report(generate_run)
    assert notes.read_text() == NOTES, _generate_report(generate_run)


@pytest.mark.parametrize(
    ("key", "expression", "integer"),
    [
        ("a", "2**100", 2**100),
        ("a", "L1*3**60", 3**60),
        ("d", "(2**60+1)", 2**60 + 1),
        ("d", "(2**53+2)/3", 2**53 + 2),  # a fraction: its numerator
        ("a", "L1*2**30*2**24", 2**54),
    ],
)
def test_integer_beyond_2_53_made_by_an_expression(key: str, expression: str, integer: int):
    """SymPy evaluates integer arithmetic exactly: "2**100" reached C as the integer literal
    1267650600228229401496703205376 (gcc: 1.49e19, NumPy: 1.27e30).  Held to the 2**53 of a
    literal: exit 2, one located line naming the integer (computed here in Python)."""
    joint = f'type = "revolute"\n{key} = "{expression}"\n{LINK}'
    outcome = run_case(("derive", *derive_argv()[1:]), {"robot.toml": robot_text(joint)})
    lines = outcome.stderr.strip().splitlines()
    assert outcome.returncode == 2 and len(lines) == 1, outcome.report()
    assert f"joint 1: '{key}' holds the integer {integer} (integers beyond 2**53" in lines[0]
    assert "Traceback" not in outcome.stderr


def test_integer_expression_at_2_53_is_allowed() -> None:
    """2**53 = 9007199254740992 is exact in double precision: the limit is inclusive."""
    joint = f'type = "revolute"\na = "L1*2**53/2**53"\nd = "2**53"\n{LINK}'
    outcome = run_case(("show", ROBOT), {"robot.toml": robot_text(joint)})
    assert outcome.returncode == 0 and "9007199254740992" in outcome.stdout, outcome.report()

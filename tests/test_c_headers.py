"""The generated C as an embedder meets it: headers a C++ program links against, units of every
output, restrict-qualified outputs, literals with the fewest digits that read back exactly."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import symkin
from codegen_helpers import CC, STRICT, write_tree
from numeric_dh import without_inertials
from symkin.cli import main
from symkin.emit.c import c_literal
from symkin.emit.printers import c_code
from symkin.generate import files_for_robot
from symkin.io import robot_from_toml
from symkin.kernels import dynamics_kernels, kinematics_kernels, point_kernels, statics_kernels
from symkin.kernels.units import determinant, unit_product

pytestmark = pytest.mark.needs_cc

CXX = shutil.which("g++") or shutil.which("c++")


@pytest.fixture(scope="module")
def planar_files() -> dict[str, str]:
    return files_for_robot(symkin.load_robot("planar_2r"), ("c",))


def headers(files: dict[str, str]) -> dict[str, str]:
    return {path: text for path, text in files.items() if path.endswith(".h")}


def run(command: list[str], cwd: Path) -> str:
    result = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, f"{' '.join(command)}:\n{result.stdout}{result.stderr}"
    return result.stdout


# ---------------------------------------------------------------- C++ embedding

CXX_PROGRAM = r"""
#include <cstdio>
#include "planar_2r.h"
#include "planar_2r_ik.h"
#include "planar_2r_ik_closed.h"

int main()
{
    const double p[2] = { 0.7, 0.4 };
    const double q[2] = { 0.3, -1.1 };
    double T[16], q_ik[2], q_closed[2 * PLANAR_2R_IK_CLOSED_MAX_SOLUTIONS];
    planar_2r_fk(q, p, T);
    int status = planar_2r_ik(T, q, p, 0, q_ik, 0);
    int count = planar_2r_ik_closed(T, p, q_closed, 0, 0);
    std::printf("%.17g %.17g %d %d\n", T[3], T[7], status, count);
    return 0;
}
"""


@pytest.mark.needs_cc
def test_a_cpp_program_links_against_the_c_build(planar_files, tmp_path):
    """Without extern "C" the C++ compiler mangles the names and the link fails."""
    assert CXX is not None, "a C++ compiler (g++) is needed; Debian's build-essential has it"
    write_tree(tmp_path, planar_files)
    c = tmp_path / "c"
    sources = ["planar_2r.c", "planar_2r_ik.c", "planar_2r_ik_closed.c"]
    run([CC, *STRICT, "-c", *sources], c)
    (c / "main.cpp").write_text(CXX_PROGRAM)
    objects = [s.replace(".c", ".o") for s in sources]
    run([CXX, "-std=c++11", "-Wall", "-Wextra", "-Werror", "-pedantic", "-o", "main",
         "main.cpp", *objects, "-lm"], c)  # fmt: skip
    x, y, status, count = run([str(c / "main")], c).split()
    # 2R closed form: x = L1 cos q1 + L2 cos(q1 + q2), y = L1 sin q1 + L2 sin(q1 + q2).
    q1, q12 = 0.3, 0.3 - 1.1
    np.testing.assert_allclose(
        [float(x), float(y)],
        [0.7 * np.cos(q1) + 0.4 * np.cos(q12), 0.7 * np.sin(q1) + 0.4 * np.sin(q12)],
        rtol=0,
        atol=1e-14,
    )
    assert (int(status), int(count)) == (0, 2)  # elbow up and elbow down


def test_every_header_has_extern_c_guards(planar_files):
    for path, text in headers(planar_files).items():
        opening = text.index('#ifdef __cplusplus\nextern "C" {\n#endif')
        closing = text.rindex("#ifdef __cplusplus\n}\n#endif")
        declarations = [m.start() for m in re.finditer(r"^\w[^#\n]*\(.*\);$", text, re.M)]
        assert declarations, path
        assert opening < min(declarations) and max(declarations) < closing, path


# ---------------------------------------------------------------- units


def all_kernels(name: str):
    model = symkin.derive(symkin.load_robot(name))
    return (
        kinematics_kernels(model)
        + dynamics_kernels(model)
        + statics_kernels(model)
        + point_kernels(model, [(1, (0.1, 0, 0))])
    )


@pytest.mark.parametrize("name", ["planar_2r", "scara"])
def test_every_output_has_units_in_the_header(name):
    kernels = all_kernels(name)
    assert all(output.units for kernel in kernels for output in kernel.outputs)
    header = files_for_robot(symkin.load_robot(name), ("c",))[f"c/{name}.h"]
    outputs = re.findall(r"^ \* (\w+)\[\d+\]: .*\n \*   units: (.+)$", header, re.M)
    assert [o for o, _ in outputs] == [o.name for k in kernels[:-1] for o in k.outputs]


def test_units_follow_the_joint_types():
    """SCARA: q1, q2 revolute, q3 prismatic (robots/scara.toml)."""
    header = files_for_robot(symkin.load_robot("scara"), ("c",))["c/scara.h"]
    assert "q: joint positions q1..q3 (rad for q1, q2; m for q3)." in header
    assert " *   units: N m for q1, q2; N for q3\n" in header
    assert "rows x y z in m and rows wx wy wz in rad, each per unit of the column's joint" in header
    assert "ddq[3]: joint accelerations; rad/s^2 for q1, q2; m/s^2 for q3" in header


def test_determinant_units_by_hand():
    """det J = (product of row units) / (product of joint units)."""
    planar = symkin.load_robot("planar_2r")  # rows x y in m, two joints in rad
    assert determinant(planar, ("x", "y")) == "m^2/rad^2"
    assert determinant(planar, ("x", "wz")) == "m/rad"
    assert unit_product({"m": 0, "rad": 0}) == "dimensionless"
    assert unit_product({"m": -1, "rad": 1}) == "rad/m"


@pytest.mark.slow  # derives the PUMA 560
def test_gravity_and_inertial_data_are_stated():
    """planar_2r without its file's inertial data gets them as pi; puma560 gives all six links
    (robot files)."""
    bare = robot_from_toml(without_inertials("planar_2r"), "planar_2r.toml")
    planar = files_for_robot(bare, ("c",))["c/planar_2r.h"]
    assert " * Gravity: (0, 0, -9.81) m/s^2 in the base frame, compiled in.\n" in planar
    assert "inertia): passed as pi for links 1, 2.\n" in planar
    stated = files_for_robot(symkin.load_robot("planar_2r"), ("c",))["c/planar_2r.h"]
    assert "inertia): compiled in for links 1, 2.\n" in stated
    puma = files_for_robot(symkin.load_robot("puma560"), ("c",))["c/puma560.h"]
    assert "inertia): compiled in for links 1, 2, 3, 4, 5, 6.\n" in puma


# ---------------------------------------------------------------- restrict

PROTOTYPE = re.compile(r"^void (\w+)\((.*)\)(;|$)", re.M)


@pytest.mark.parametrize("suffix, word", [(".h", "SYMKIN_RESTRICT"), (".c", "restrict")])
def test_outputs_are_restrict(planar_files, suffix, word):
    text = planar_files[f"c/planar_2r{suffix}"]
    prototypes = PROTOTYPE.findall(text)
    assert len(prototypes) > 20
    for name, parameters, _ in prototypes:
        outputs = [p for p in parameters.split(", ") if not p.startswith(("const", "size_t"))]
        assert outputs, name
        assert all(word in p for p in outputs), (name, outputs)
        assert all(word not in p for p in parameters.split(", ") if p not in outputs), name


# ---------------------------------------------------------------- literals


def significant_digits(text: str) -> int:
    mantissa = text.rstrip("F").lstrip("-").split("e")[0].replace(".", "").lstrip("0")
    return len(mantissa.rstrip("0")) or 1


def shorter_round_trips(value, text: str, cast) -> bool:
    """Whether some decimal with one significant digit fewer reads back as ``value``."""
    digits = significant_digits(text)
    return digits > 1 and cast(f"{float(value):.{digits - 2}e}") == value


VALUES = [0.1, 1.0, 2.0, 0.735522, 9.81, 1e-30, 1e-5, 123456789.0, 2.0**-53, np.pi, 2 * np.pi,
          3.4028234663852886e38, 1.1754943508222875e-38, 0.30000001192092896, -0.4318]  # fmt: skip
RANDOM = np.random.default_rng(7).lognormal(0, 8, 200) * np.random.default_rng(8).choice(
    [-1, 1], 200
)


@pytest.mark.parametrize("precision, cast", [("float", np.float32), ("double", np.float64)])
def test_literals_are_the_shortest_that_read_back(precision, cast):
    for value in [*VALUES, *RANDOM]:
        exact = cast(value)
        text = c_literal(value, precision)
        assert text.endswith("F") == (precision == "float"), text
        number = text.rstrip("F")
        assert "." in number or "e" in number, text  # a floating constant, not an integer
        assert cast(number) == exact, (value, text)
        assert not shorter_round_trips(exact, text, cast), (value, text)


def test_printed_numbers_are_the_shortest():
    x = sp.Symbol("x", real=True)
    assert c_code(sp.Float("0.735522") * x, "double") == "0.735522*x"
    assert c_code(sp.Float("0.735522") * x, "float") == "0.735522F*x"
    assert c_code(sp.pi * x, "float") == "3.1415927F*x"
    assert c_code(sp.Float("1e-30") * x, "float") == "1e-30F*x"


@pytest.mark.needs_cc
def test_float_literals_compile_to_the_same_numbers(tmp_path):
    """The C compiler reads every literal back as numpy's float32 of the value."""
    values = [*VALUES, *RANDOM[:50]]
    body = "\n".join(f'    printf("%a\\n", (double){c_literal(v, "float")});' for v in values)
    (tmp_path / "l.c").write_text(
        f"#include <stdio.h>\nint main(void)\n{{\n{body}\n    return 0;\n}}\n"
    )
    run([CC, *STRICT, "-Wconversion", "-Wdouble-promotion", "-o", "l", "l.c"], tmp_path)
    printed = run([str(tmp_path / "l")], tmp_path).split()
    assert [np.float32(float.fromhex(t)) for t in printed] == [np.float32(v) for v in values]


# ---------------------------------------------------------------- regenerate line


def test_the_regenerate_line_carries_the_flags_and_reproduces_the_files(tmp_path):
    first = tmp_path / "first"
    argv = ["scara", "--emit", "c,numpy", "--precision", "float", "--numeric-parameters"]
    argv += ["--set", "L1=0.4", "--point", "2:0.1,0,0"]
    assert main(["derive", argv[0], "--out", str(first), *argv[1:]]) == 0
    files = {
        p.relative_to(first): p.read_text()
        for p in first.rglob("*")
        if p.is_file() and p.name != ".symkin-files"  # the manifest lists what was asked for
    }
    lines = {
        re.search(r"Regenerate with: (.*)", t).group(1) for t in files.values() if "Regenerate" in t
    }
    # --emit chooses files, not their text: the line leaves it out and regenerates them all
    assert lines == {f"symkin derive scara --out DIR {' '.join(argv[3:])}"}
    command = lines.pop().replace("DIR", str(tmp_path / "again")).split()
    assert main(command[1:]) == 0
    again = tmp_path / "again"
    assert {name: (again / name).read_text() for name in files} == files

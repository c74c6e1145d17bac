"""The wrench, statics and energy kernels print the same numbers in every backend: NumPy
(checked against independent sources in test_wrench_energy.py), C double and float through
ctypes, the CPython extension (single states and batches) and CasADi."""

from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np
import pytest

import symkin
from codegen_helpers import CC, SHARED, STRICT, import_path, run_parallel
from symkin.cli import main
from symkin.kernels import statics_kernels
from symkin.runtime.extension import load_extension

pytestmark = [pytest.mark.needs_cc, pytest.mark.slow]

NAMES = ("planar_2r", "rpr")
KERNELS = ("wrench_torque", "static_torque", "energy")
INPUTS = {"q": 1.5, "dq": 2.0, "wrench": 10.0}


class Built:
    def __init__(self, name: str, root: Path) -> None:
        assert main(["derive", name, "--out", str(root), "--emit", "numpy,c,python,casadi"]) == 0
        builds = run_parallel(
            {
                "so": [CC, *STRICT, *SHARED, "-o", "libk.so", f"c/{name}.c", "-lm"],
            },
            cwd=root,
        )
        builds["so"].check()
        self.robot = symkin.load_robot(name)
        self.kernels = {k.name: k for k in statics_kernels(symkin.derive(self.robot))}
        self.numpy = import_path(f"wrench_{name}_numpy", root / "numpy" / f"{name}_kinematics.py")
        self.casadi = import_path(f"wrench_{name}_casadi", root / "casadi" / f"{name}_casadi.py")
        self.extension = load_extension(next((root / "python").glob(f"{name}_ext*.so")))
        self.lib = ctypes.CDLL(str(root / "libk.so"))
        self.name = name
        rng = np.random.default_rng(18)
        self.p = self.numpy.DEFAULT_PARAMETERS
        self.pi = rng.uniform(0.2, 1.0, 10 * self.robot.dof)

    def states(self, kernel: str, count: int, seed: int) -> list[np.ndarray]:
        rng = np.random.default_rng(seed)
        names = [i.name for i in self.kernels[kernel].inputs if i.name in INPUTS]
        sizes = {"wrench": 6}
        return [
            rng.uniform(-1, 1, (count, sizes.get(n, self.robot.dof))) * INPUTS[n] for n in names
        ]

    def takes_pi(self, kernel: str) -> bool:
        return any(i.name == "pi" for i in self.kernels[kernel].inputs)

    def call_c(self, kernel: str, states: list[np.ndarray]) -> np.ndarray:
        arrays = [*states, self.p] + ([self.pi] if self.takes_pi(kernel) else [])
        arrays = [np.ascontiguousarray(a, dtype=float) for a in arrays]
        outputs = self.kernels[kernel].outputs
        buffers = [np.full(o.size, np.nan) for o in outputs]
        function = getattr(self.lib, f"{self.name}_{kernel}")
        function.restype = None
        function.argtypes = [ctypes.c_void_p] * (len(arrays) + len(buffers))
        function(*[a.ctypes.data_as(ctypes.c_void_p) for a in [*arrays, *buffers]])
        return np.concatenate(buffers)


@pytest.fixture(scope="module", params=NAMES)
def built(request, tmp_path_factory) -> Built:
    return Built(request.param, tmp_path_factory.mktemp(f"wrench_{request.param}"))


def _flat(result) -> np.ndarray:
    parts = result if isinstance(result, tuple) else (result,)
    return np.concatenate([np.ravel(np.asarray(part, dtype=float)) for part in parts])


@pytest.mark.parametrize("kernel", KERNELS)
def test_every_backend_agrees_with_numpy(built, kernel):
    extra = {"pi": built.pi} if built.takes_pi(kernel) else {}
    batch = built.states(kernel, 5, seed=KERNELS.index(kernel))
    numpy_batch = getattr(built.numpy, kernel)(*batch, built.p, **extra)
    extension_batch = getattr(built.extension, kernel)(*batch, built.p, **extra)
    for got, want in zip(_as_tuple(extension_batch), _as_tuple(numpy_batch), strict=True):
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)
    function = getattr(built.casadi, f"{kernel}_function")()
    for k in range(5):
        single = [s[k] for s in batch]
        expected = _flat(getattr(built.numpy, kernel)(*single, built.p, **extra))
        np.testing.assert_allclose(built.call_c(kernel, single), expected, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(
            _flat(getattr(built.extension, kernel)(*single, built.p, **extra)), expected, atol=1e-12
        )
        arguments = [*single, built.p] + ([built.pi] if extra else [])
        casadi_out = function(*arguments)
        casadi_flat = _flat(
            tuple(np.array(v.full()) for v in casadi_out)
            if isinstance(casadi_out, tuple | list)
            else np.array(casadi_out.full())
        )
        np.testing.assert_allclose(casadi_flat, expected, rtol=1e-12, atol=1e-12)


def _as_tuple(value):
    return value if isinstance(value, tuple) else (value,)


def test_extension_rejects_a_wrench_of_the_wrong_size(built):
    q = np.zeros(built.robot.dof)
    with pytest.raises(ValueError, match=r"the wrench: \(6,\) or \(N, 6\)"):
        built.extension.wrench_torque(q, np.zeros(5))

"""Names a robot file may not use, because generated code or SymPy already does.

A parameter becomes a local variable in every generated kernel (C, NumPy, CasADi, the
CPython extension) and a SymPy symbol in the derivation.  A parameter named ``M`` would be
overwritten by the mass-matrix output, ``fabs`` would hide C's function, ``NAN`` is a C
macro: the code would compile, or not, and give wrong numbers.  :func:`reserved_reason` is
the one check; the loader rejects such names with its answer (docs/robot-files.md).  The
kernel layer's names (:data:`KERNEL_NAMES`, :data:`KERNEL_OUTPUTS`, ...) are listed here so
that a test can hold the kernels to them.
"""

from __future__ import annotations

import builtins
import keyword
import re

SYMPY_NAMES = frozenset(
    {
        "pi", "E", "I", "S", "N", "O", "Q", "oo", "zoo", "nan", "inf",
        "sin", "cos", "tan", "cot", "sec", "csc", "asin", "acos", "atan", "atan2",
        "sinh", "cosh", "tanh", "exp", "log", "ln", "sqrt", "cbrt", "abs", "Abs",
        "sign", "sgn", "min", "max", "Min", "Max", "floor", "ceiling", "re", "im",
    }
)  # fmt: skip

C_KEYWORDS = frozenset(
    {
        "auto", "break", "case", "char", "const", "continue", "default", "do", "double",
        "else", "enum", "extern", "float", "for", "goto", "if", "inline", "int", "long",
        "register", "restrict", "return", "short", "signed", "sizeof", "static", "struct",
        "switch", "typedef", "union", "unsigned", "void", "volatile", "while", "_Bool",
        "_Complex", "_Imaginary", "_Alignas", "_Alignof", "_Atomic", "_Generic", "_Noreturn",
        "_Static_assert", "_Thread_local", "bool", "true", "false", "asm", "typeof",
    }
)  # fmt: skip

# <math.h> functions (double, float and long double forms) and macros, and the names of the
# other headers generated C includes (<stddef.h>, <stdint.h>, <string.h>, <stdio.h>).
_MATH_FUNCTIONS = (
    "acos asin atan atan2 cos sin tan acosh asinh atanh cosh sinh tanh exp exp2 expm1 frexp "
    "ilogb ldexp log log10 log1p log2 logb modf scalbn scalbln cbrt fabs hypot pow sqrt erf "
    "erfc lgamma tgamma ceil floor nearbyint rint lrint llrint round lround llround trunc "
    "fmod remainder remquo copysign nan nextafter nexttoward fdim fmax fmin fma"
)
C_LIBRARY_NAMES = frozenset(
    {f + suffix for f in _MATH_FUNCTIONS.split() for suffix in ("", "f", "l")}
    | set(
        [
            "HUGE_VAL",
            "HUGE_VALF",
            "HUGE_VALL",
            "INFINITY",
            "NAN",
            "FP_INFINITE",
            "FP_NAN",
            "FP_NORMAL",
            "FP_SUBNORMAL",
            "FP_ZERO",
            "FP_ILOGB0",
            "FP_ILOGBNAN",
            "MATH_ERRNO",
            "MATH_ERREXCEPT",
            "math_errhandling",
            "fpclassify",
            "isfinite",
            "isinf",
            "isnan",
            "isnormal",
            "signbit",
            "isgreater",
            "isgreaterequal",
            "isless",
            "islessequal",
            "islessgreater",
            "isunordered",
            "float_t",
            "double_t",
            "M_PI",
            "M_E",
            "NULL",
            "size_t",
            "ptrdiff_t",
            "offsetof",
            "wchar_t",
            "uint64_t",
            "int64_t",
            "uint32_t",
            "int32_t",
            "uint8_t",
            "int8_t",
            "uintptr_t",
            "intptr_t",
            "UINT64_C",
            "memcpy",
            "memset",
            "strcmp",
            "strlen",
            "printf",
            "snprintf",
            "sprintf",
            "fprintf",
            "stdout",
            "stderr",
            "main",
            "errno",
            "assert",
            "exit",
            "malloc",
            "free",
        ]
    )
)

PYTHON_NAMES = frozenset(
    {*keyword.kwlist, *keyword.softkwlist, *dir(builtins), "numpy", "casadi", "math", "np", "ca"}
)

# What the kernel layer names its functions, inputs and outputs (symkin.kernels), and the
# locals the templates declare in a kernel's scope (templates/*/).
KERNEL_NAMES = frozenset(
    {
        "fk", "jacobian", "fk_jacobian", "position", "position_jacobian", "det",
        "manipulability", "mass_matrix", "gravity", "coriolis", "coriolis_matrix",
        "mass_matrix_bias", "inverse_dynamics", "forward_dynamics", "wrench_torque",
        "static_torque", "energy",
        "elastic_constants", "elastic_inverse_dynamics", "elastic_forward_dynamics",
    }
)  # fmt: skip
KERNEL_INPUTS = frozenset({"q", "dq", "ddq", "tau", "p", "pi", "wrench", "d3q", "d4q"})
KERNEL_OUTPUTS = frozenset(
    {"T", "J", "Jp", "p_tool", "det", "mu", "M", "G", "c", "C", "bias", "tau", "ddq",
     "p_point", "v_point", "a_point", "tau_w", "tau_s", "kinetic", "potential", "lagrangian",
     "K_spring", "B_motor", "theta_m", "tau_m", "ddtheta"}
)  # fmt: skip
TEMPLATE_LOCALS = frozenset(
    {
        "i", "count", "batch", "bias", "extra", "mass", "rhs", "symbol_type", "constants",
        "out", "args", "self", "module", "DOF", "DEFAULT_PARAMETERS", "PARAMETER_NAMES",
        "SX", "MX", "DM", "Function",
    }
)  # fmt: skip
# Point kernels are named point1, point2, ... (symkin.kernels.point_kernels).
GENERATED_PATTERN = re.compile(r"point[0-9]+")

# Types and macros of the C library generated code pastes (templates/c/lib); its functions
# and other macros are all symkin_* / SYMKIN_*.
C_LIBRARY_TYPES = frozenset({"real_t", "REAL"})

# A robot's name becomes a file name: <name>.h must not shadow a standard C header.
C_HEADERS = frozenset(
    [
        "assert",
        "complex",
        "ctype",
        "errno",
        "fenv",
        "float",
        "inttypes",
        "iso646",
        "limits",
        "locale",
        "math",
        "setjmp",
        "signal",
        "stdalign",
        "stdarg",
        "stdatomic",
        "stdbool",
        "stddef",
        "stdint",
        "stdio",
        "stdlib",
        "stdnoreturn",
        "string",
        "tgmath",
        "threads",
        "time",
        "uchar",
        "wchar",
        "wctype",
        "Python",
        "numpy",
    ]
)


def reserved_reason(name: str) -> str | None:
    """Why a parameter may not be called ``name`` (``None``: it may)."""
    if name in SYMPY_NAMES:
        return "a SymPy constant or function"
    if name in C_KEYWORDS:
        return "a C keyword"
    if name in C_LIBRARY_NAMES:
        return "a C library name that generated code uses or includes"
    if name in PYTHON_NAMES:
        return "a Python keyword, built-in or module name"
    if name in KERNEL_NAMES | KERNEL_INPUTS | KERNEL_OUTPUTS | TEMPLATE_LOCALS or (
        GENERATED_PATTERN.fullmatch(name)
    ):
        return "a name the generated code gives to its own functions, inputs or outputs"
    if name.startswith("_"):
        return "names starting with '_' are reserved for generated intermediates"
    if name in C_LIBRARY_TYPES or name.lower() == "symkin" or name.lower().startswith("symkin_"):
        return "a name of the C library pasted into generated code (templates/c/lib)"
    return None


def robot_name_reason(name: str) -> str | None:
    """Why a robot may not be called ``name`` (its C header would be ``<name>.h``)."""
    if name in C_HEADERS:
        return f"the generated C header {name}.h would hide the standard header <{name}.h>"
    if name in C_KEYWORDS or name in PYTHON_NAMES:
        return "a C or Python keyword"
    if name == "example":
        return "the C backend writes its demo program to example.c"
    if name == "symkin" or name.startswith("symkin_"):
        # The C library pasted into generated files (templates/c/lib) owns symkin_* and
        # SYMKIN_*: a robot there would redeclare symkin_fk_jacobian, SYMKIN_RESTRICT, ...
        return "the generated C library's functions and macros are named symkin_* and SYMKIN_*"
    return None

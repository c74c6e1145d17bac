"""Seeded random serial arms for the scaling benchmarks and profiling (issue 15).

``random_arm_toml(n, seed)`` writes a symkin robot file (standard DH, radians) whose every
``a`` and ``d`` is non-zero, so no link collapses and the algebra has no textbook shortcut.
Twists come from ``{0, +-90 deg}`` (``twists="right"``) or are generic angles
(``twists="generic"``: 15..165 deg, either sign); lengths are numbers (``lengths="numeric"``)
or named parameters with those numbers as defaults (``lengths="symbolic"``).  With
``dynamics=True`` every link gets a plausible rod-like mass, centre of mass and inertia.

``jaco_like_toml()`` is the 6R arm of the issue: 60-degree wrist twists and wrist offsets.
"""

from __future__ import annotations

import math
import random

TWIST_CHOICES = ("right", "generic")
LENGTH_CHOICES = ("numeric", "symbolic")


def _number(value: float) -> str:
    return f"{value:.4f}"


def _length(name: str, value: float, lengths: str, parameters: dict[str, str]) -> str:
    if lengths == "numeric":
        return _number(value)
    parameters[name] = _number(value)
    return f'"{name}"'


def _link_table(rng: random.Random, a: float, d: float) -> list[str]:
    mass = round(rng.uniform(0.5, 5.0), 3)
    length = max(abs(a), abs(d))
    rod = round(mass * length**2 / 12, 5)
    com = [round(-a / 2, 4), round(rng.uniform(-0.02, 0.02), 4), round(-d / 2, 4)]
    return [
        "[joints.link]",
        f"mass = {mass}",
        f"com = [{com[0]}, {com[1]}, {com[2]}]",
        "inertia = { "
        + f"ixx = {round(rod / 2 + 1e-3, 5)}, iyy = {rod + 1e-3}, izz = {rod + 1e-3}, "
        + "ixy = 0, ixz = 0, iyz = 0 }",
        "",
    ]


def random_arm_toml(
    n: int,
    seed: int,
    twists: str = "right",
    lengths: str = "numeric",
    dynamics: bool = False,
) -> str:
    """A robot file of an ``n``-joint revolute arm drawn from ``seed`` (see module doc)."""
    if twists not in TWIST_CHOICES or lengths not in LENGTH_CHOICES:
        raise ValueError(f"twists in {TWIST_CHOICES}, lengths in {LENGTH_CHOICES}")
    rng = random.Random(f"{n}-{seed}-{twists}-{lengths}")
    parameters: dict[str, str] = {}
    rows: list[str] = []
    for i in range(1, n + 1):
        a = rng.choice((-1, 1)) * rng.uniform(0.05, 0.5)
        d = rng.choice((-1, 1)) * rng.uniform(0.05, 0.3)
        if twists == "right":
            alpha = rng.choice((0.0, math.pi / 2, -math.pi / 2))
            alpha_text = {0.0: "0", math.pi / 2: '"pi/2"', -math.pi / 2: '"-pi/2"'}[alpha]
        else:
            alpha_text = _number(rng.choice((-1, 1)) * math.radians(rng.uniform(15, 165)))
        rows += [
            "[[joints]]",
            'type = "revolute"',
            f"a = {_length(f'a{i}', a, lengths, parameters)}",
            f"d = {_length(f'd{i}', d, lengths, parameters)}",
            f"alpha = {alpha_text}",
            "limits = [-3.1416, 3.1416]",
            "",
        ]
        if dynamics:
            rows += _link_table(rng, a, d)
    name = f"random_{n}r_{twists}_{lengths}_{seed}"
    head = [
        f'name = "{name}"',
        f'title = "Seeded random {n}R arm ({twists} twists, {lengths} lengths, seed {seed})"',
        'convention = "standard"',
        'angles = "rad"',
        "",
    ]
    if parameters:
        head += ["[parameters]", *(f"{k} = {v}" for k, v in parameters.items()), ""]
    return "\n".join(head + rows)


def jaco_like_toml() -> str:
    """The issue's Kinova-Jaco-like 6R arm: standard DH, twists 90/180/90/60/60/180 deg,
    wrist offsets d4..d6 and the shoulder offset (numbers from Kinova's Jaco v2 6-DOF
    spherical-less wrist table, rounded)."""
    alphas = ("pi/2", "pi", "pi/2", "pi/3", "pi/3", "pi")
    a = ("0", "0.41", "0", "0", "0", "0")
    d = ("0.2755", "0", "-0.0098", "-0.2501", "-0.0856", "-0.2028")
    rows = [
        'name = "jaco_like"',
        'title = "Kinova-Jaco-like 6R arm (60-degree wrist twists, wrist offsets)"',
        'convention = "standard"',
        'angles = "rad"',
        "",
    ]
    for alpha, ai, di in zip(alphas, a, d, strict=True):
        rows += [
            "[[joints]]",
            'type = "revolute"',
            f"a = {ai}",
            f"d = {di}",
            f'alpha = "{alpha}"',
            "limits = [-3.1416, 3.1416]",
            "",
        ]
    return "\n".join(rows)


def toml_from_spec(spec: str) -> str | None:
    """The robot file of ``random:N:SEED:TWISTS:LENGTHS`` (with dynamics) or ``jaco`` (the
    benches' command-line shorthand); ``None`` for anything else (a path or catalogue name)."""
    if spec == "jaco":
        return jaco_like_toml()
    if spec.startswith("random:"):
        _, n, seed, twists, lengths = spec.split(":")
        return random_arm_toml(int(n), int(seed), twists, lengths, dynamics=True)
    return None

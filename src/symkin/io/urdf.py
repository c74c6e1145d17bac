"""URDF files -> :class:`~symkin.robot.Robot` in the placement form.

Parsed with ``urdfdom-py`` (``urdf_parser_py``, the ROS reference parser; no meshes are read,
docs/dependencies.md says why this library).  The robot is the serial chain from the ``base``
link (default: the tree's root) to the ``tip`` link (default: the one leaf below the base):

* revolute and continuous joints become revolute joints, prismatic joints prismatic ones;
  fixed joints fold into the next joint's origin, and those after the last moving joint into
  the tool transform, so ``T`` is the pose of the tip link in the base link frame;
* each joint's ``origin`` and ``axis`` become a canonical placement
  (:func:`symkin.io.placement.canonical_joints`);
* the moving body of joint i is its child link plus every link hung from it by fixed joints
  and every side branch that leaves the chain (those joints held at zero, e.g. the Panda's
  fingers when the tip is its hand, said once as a warning); their ``<inertial>`` data are
  lumped into one rigid body (:mod:`symkin.io.urdf_inertia`);
* ``<limit lower upper velocity effort>`` are carried (continuous joints have no position
  limits); ``<dynamics damping friction>`` is not read;
* gravity is 9.81 m/s^2 along -z of the base link;
* joint names are the URDF's where they are identifiers (other characters made ``_``); they
  label the joints in ``show`` and the placement table, while the joint variables stay
  ``q1 .. qn`` (generated code needs them valid in every language);

Every problem in the file is one :class:`~symkin.errors.RobotError` naming the file and the
joint or link: malformed XML, a missing link, a loop, floating, planar or mimic joints on the
chain, a zero axis; repeated names, numbers that are not finite, a negative mass, an inertia
tensor that is not positive semi-definite, ``lower > upper`` (:mod:`symkin.io.urdf_checks`);
a non-unit axis is normalised and said once.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import sympy as sp

from symkin.errors import RobotError, RobotWarning
from symkin.io.context import did_you_mean
from symkin.io.placement import (
    canonical_joints,
    exact_angle,
    exact_number,
    unit_axis,
    warn_normalised,
)
from symkin.io.urdf_checks import check_urdf_model
from symkin.io.urdf_inertia import body_link
from symkin.names import robot_name_reason
from symkin.robot import MAX_NAME_LENGTH, NAME_PATTERN, Joint, Link, Robot
from symkin.spatial import rotation_from_rpy, transform_from_rotation_translation

__all__ = ["robot_from_urdf"]

MOVING = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}
UNSUPPORTED = ("floating", "planar")
IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
IGNORED_ELEMENTS = "transmission|gazebo|material|link/visual|link/collision"


@dataclass(frozen=True)
class Tree:
    """The kinematic tree of a URDF: links by name, the joint above each link, the joints
    below each link (file order)."""

    file: str
    links: dict[str, Any]
    parent_joint: dict[str, Any]
    child_joints: dict[str, list[Any]]

    def below(self, link: str, skip: Any = None) -> Iterator[tuple[Any, str]]:
        """``(joint, link)`` of every link under ``link`` (depth first), not through ``skip``."""
        for joint in self.child_joints.get(link, []):
            if joint is skip:
                continue
            yield joint, joint.child
            yield from self.below(joint.child, skip)


# ---------------------------------------------------------------------------------------------
# Public API
# ---------------------------------------------------------------------------------------------


def robot_from_urdf(
    text: str | bytes, file: str, tip: str | None = None, base: str | None = None
) -> Robot:
    """The serial chain of a URDF document from ``base`` to ``tip`` (module docstring).

    ``file`` names the document in messages and in ``Robot.file``.  Raises
    :class:`RobotError` for anything the file or the choice of links gets wrong.
    """
    model = _parse(text, file)
    check_urdf_model(model, file)
    tree = _tree(model, file)
    base = _base_link(tree, base)
    tip = _tip_link(tree, base, tip)
    chain = _chain(tree, base, tip)
    joints, axes, tool = _placed_joints(tree, chain)
    placed, tool = canonical_joints(joints, axes, tool)
    name = _robot_name(model.name)
    try:
        return Robot(
            name=name,
            joints=placed,
            convention="placement",
            tool=tool,
            title=f"{model.name or name} (URDF), from link {base} to link {tip}",
            source=Path(file).name,
            file=file,
        )
    except RobotError as exc:
        raise RobotError(f"{file}: {exc}") from None


# ---------------------------------------------------------------------------------------------
# Parsing and the tree
# ---------------------------------------------------------------------------------------------


def _parse(text: str | bytes, file: str) -> Any:
    # Imported here: only URDF loading pays for the parser (and lxml).
    from lxml import etree
    from urdf_parser_py import urdf
    from urdf_parser_py.xml_reflection import core

    data = text.encode("utf-8") if isinstance(text, str) else text
    # The parser reports unknown tags on stderr through this hook; they are legal URDF
    # extensions that carry nothing symkin reads.
    quiet, core.on_error = core.on_error, lambda message: None
    try:
        node = etree.fromstring(data, etree.XMLParser(resolve_entities=False, no_network=True))
        # Elements symkin never reads, removed before the strict parser sees them: it rejects
        # real files over them (PR2's old-style <transmission>, iCub's <texture> without a
        # filename, both in example-robot-data) that Pinocchio and ROS load.
        for element in node.xpath(IGNORED_ELEMENTS):
            element.getparent().remove(element)
        return urdf.URDF.from_xml(
            node, core.Path(urdf.URDF.XML_REFL.tag, tree=etree.ElementTree(node))
        )
    except Exception as exc:  # lxml, xml_reflection and plain errors for bad values
        detail = " ".join(str(exc).split()) or type(exc).__name__
        raise RobotError(f"{file}: not a valid URDF: {detail}") from None
    finally:
        core.on_error = quiet


def _tree(model: Any, file: str) -> Tree:
    links = {link.name: link for link in model.links}
    parent_joint: dict[str, Any] = {}
    child_joints: dict[str, list[Any]] = {}
    for joint in model.joints:
        for role in ("parent", "child"):
            name = getattr(joint, role)
            if name not in links:
                raise RobotError(
                    f"{file}: joint {joint.name!r}: {role} link {name!r} does not exist"
                    f"{did_you_mean(str(name), links)}"
                )
        if joint.child in parent_joint:
            other = parent_joint[joint.child].name
            raise RobotError(
                f"{file}: link {joint.child!r} is the child of joints {other!r} and "
                f"{joint.name!r}: a loop (a URDF is a tree, each link has one parent)"
            )
        parent_joint[joint.child] = joint
        child_joints.setdefault(joint.parent, []).append(joint)
    if not links:
        raise RobotError(f"{file}: the URDF has no links")
    tree = Tree(file, links, parent_joint, child_joints)
    _check_no_cycle(tree)
    return tree


def _check_no_cycle(tree: Tree) -> None:
    for start in tree.links:
        seen, link = {start}, start
        while link in tree.parent_joint:
            link = tree.parent_joint[link].parent
            if link in seen:
                raise RobotError(
                    f"{tree.file}: a loop through link {link!r} (joint "
                    f"{tree.parent_joint[link].name!r}); a URDF is a tree"
                )
            seen.add(link)


def _base_link(tree: Tree, base: str | None) -> str:
    if base is not None:
        _check_link(tree, base, "base")
        return base
    roots = [name for name in tree.links if name not in tree.parent_joint]
    if len(roots) != 1:
        raise RobotError(
            f"{tree.file}: {len(roots)} root links ({', '.join(roots)}); a URDF has one root"
        )
    return roots[0]


def _check_link(tree: Tree, name: str, role: str) -> None:
    if name not in tree.links:
        raise RobotError(
            f"{tree.file}: the {role} link {name!r} does not exist{did_you_mean(name, tree.links)}"
        )


def _tip_link(tree: Tree, base: str, tip: str | None) -> str:
    if tip is not None:
        _check_link(tree, tip, "tip")
        return tip
    leaves = [link for _, link in tree.below(base) if link not in tree.child_joints]
    if len(leaves) > 1:
        raise RobotError(
            f"{tree.file}: the tree below link {base!r} has {len(leaves)} leaves "
            f"({', '.join(leaves)}); choose the tip link (symkin: --tip LINK)"
        )
    if not leaves:
        raise RobotError(f"{tree.file}: link {base!r} has no joints below it")
    return leaves[0]


def _chain(tree: Tree, base: str, tip: str) -> list[Any]:
    """The joints from ``base`` down to ``tip``, in order."""
    chain, link = [], tip
    while link != base:
        if link not in tree.parent_joint:
            raise RobotError(f"{tree.file}: the tip link {tip!r} is not below the base {base!r}")
        joint = tree.parent_joint[link]
        chain.append(joint)
        link = joint.parent
    chain.reverse()
    for joint in chain:
        if joint.type in UNSUPPORTED:
            raise RobotError(
                f"{tree.file}: joint {joint.name!r} is {joint.type}; symkin reads serial "
                "chains of revolute, continuous, prismatic and fixed joints"
            )
        if joint.type not in MOVING and joint.type != "fixed":
            raise RobotError(f"{tree.file}: joint {joint.name!r} has unknown type {joint.type!r}")
        if joint.mimic is not None:
            raise RobotError(
                f"{tree.file}: joint {joint.name!r} mimics joint {joint.mimic.joint!r}; "
                "mimic joints are not supported on the chain"
            )
    if not any(joint.type in MOVING for joint in chain):
        raise RobotError(f"{tree.file}: no moving joint between link {base!r} and link {tip!r}")
    return chain


# ---------------------------------------------------------------------------------------------
# Joints
# ---------------------------------------------------------------------------------------------


def origin_transform(joint: Any) -> sp.Matrix:
    """A joint's ``<origin>`` as a 4x4 SymPy transform (``R = Rz(y) Ry(p) Rx(r)``)."""
    pose = joint.origin
    xyz = [0.0] * 3 if pose is None or pose.xyz is None else pose.xyz
    rpy = [0.0] * 3 if pose is None or pose.rpy is None else pose.rpy
    rotation = rotation_from_rpy(*(exact_angle(float(a)) for a in rpy))
    translation = sp.Matrix([exact_number(float(v)) for v in xyz])
    return sp.Matrix(transform_from_rotation_translation(rotation, translation))


def _placed_joints(
    tree: Tree, chain: Sequence[Any]
) -> tuple[list[Joint], list[tuple[sp.Expr, ...]], sp.Matrix]:
    """URDF-sense placed joints (origin from the parent link frame with the fixed joints
    before it folded in), their unit axes and the fixed transform after the last one."""
    moving = [joint for joint in chain if joint.type in MOVING]
    lumped: list[str] = []
    joints, axes, fixed, names = [], [], sp.eye(4), _joint_names(moving)
    for index, joint in enumerate(chain):
        fixed = fixed * origin_transform(joint)
        if joint.type not in MOVING:
            continue
        later = [j for j in chain[index + 1 :] if j.type in MOVING]
        link, side = body_link(tree, joint.child, later[0] if later else None)
        lumped += side
        axis, limits = _axis(tree.file, joint), _limits(joint)
        joints.append(
            Joint(
                type=MOVING[joint.type],  # type: ignore[arg-type]
                name=names[joint.name],
                limits=limits,
                link=link,
                placement=sp.ImmutableMatrix(fixed),
                max_velocity=_positive(tree.file, joint, "velocity"),
                max_effort=_positive(tree.file, joint, "effort"),
            )
        )
        axes.append(axis)
        fixed = sp.eye(4)
    if lumped:
        warnings.warn(
            f"{tree.file}: joints off the chain are held at zero and their links lumped into "
            f"the chain's links: {', '.join(lumped)}",
            RobotWarning,
            stacklevel=3,
        )
    return _no_inertial_means_massless(joints), axes, fixed


def _axis(file: str, joint: Any) -> tuple[sp.Expr, ...]:
    raw = [1.0, 0.0, 0.0] if joint.axis is None else [float(v) for v in joint.axis]
    where = f"{file}: joint {joint.name!r}"
    axis, normalised = unit_axis(raw, where)
    if normalised:
        warn_normalised(where, raw)
    return axis


def _limits(joint: Any) -> tuple[float, float] | None:
    limit = joint.limit
    if joint.type == "continuous" or limit is None or limit.lower is None or limit.upper is None:
        return None
    low, high = float(limit.lower), float(limit.upper)
    return (low, high) if low < high else None


def _positive(file: str, joint: Any, key: str) -> float | None:
    """``<limit velocity>`` or ``effort``: ``None`` when absent or 0 (URDF files write 0 for
    "not given"); a negative value is an error, not dropped."""
    value = None if joint.limit is None else getattr(joint.limit, key, None)
    if value is not None and float(value) < 0:
        raise RobotError(
            f"{file}: joint {joint.name!r}: <limit {key}> must be positive (0: not given), "
            f"got {float(value):g}"
        )
    return float(value) if value is not None and float(value) > 0 else None


def _no_inertial_means_massless(joints: list[Joint]) -> list[Joint]:
    """URDF: a link without ``<inertial>`` has no mass.  When some bodies of the chain have
    data, the others get a zero-mass link; when none has, the robot has no inertial data
    (symkin then asks for the inertial parameters when dynamics need numbers)."""
    if all(joint.link is None for joint in joints):
        return joints
    zero = Link(mass=sp.Integer(0), com=(0, 0, 0), inertia=(0, 0, 0, 0, 0, 0))  # type: ignore[arg-type]
    return [joint if joint.link else replace(joint, link=zero) for joint in joints]


def _joint_names(joints: Sequence[Any]) -> dict[str, str | None]:
    """URDF joint name -> symkin joint name: kept when it is an identifier (ASCII letters,
    digits, ``_``), else with every other character made ``_``; None for a repeat."""
    names: dict[str, str | None] = {}
    used: set[str] = set()
    for joint in joints:
        name = re.sub(r"[^A-Za-z0-9_]", "_", str(joint.name))
        if not IDENTIFIER.match(name):
            name = f"joint_{name}"
        names[joint.name] = None if name in used else name
        used.add(name)
    return names


def _robot_name(urdf_name: str | None) -> str:
    """The URDF's robot name made a symkin robot name (``[a-z][a-z0-9_]*``, not reserved, at
    most ``MAX_NAME_LENGTH`` characters)."""
    name = re.sub(r"[^a-z0-9_]", "_", (urdf_name or "robot").lower())
    if not NAME_PATTERN.match(name):
        name = f"robot_{name}"
    name = name[: MAX_NAME_LENGTH - len("_robot")]
    if robot_name_reason(name):
        name = f"{name}_robot"
    return name

"""Any robot as URDF text (``symkin urdf ROBOT -o FILE``).

Frames: the URDF link of joint i is the joint's axis frame (z along the axis, pointing where
``q_i`` grows; :attr:`Kinematics.joint_frames`) carried by the joint's own motion, so every
``<joint>`` has ``<axis xyz="0 0 1"/>`` and a constant ``<origin>``: the pose of that frame at
``q_i = 0`` in the parent link's frame, computed at ``q = 0``.  The root link ``base_link``
is the frame the robot's ``base`` transform is given in; a fixed joint carries the tool frame
(link ``tool``).  Inertials keep their tensor in the robot's link frame (axes of frame i) and
put that frame's pose into the inertial ``<origin>`` (URDF: the tensor is expressed in the
inertial frame).  URDF needs ``effort`` and ``velocity`` on revolute and prismatic limits;
they come from the joint's ``max_effort`` and ``max_velocity``, 0 ("unknown", docs/cli.md) when
the robot has none.  A
revolute joint without limits is ``continuous``; a prismatic joint without limits gets
``[-1, 1]`` m.  Each link gets a cylinder visual from its origin to the next joint's origin.
"""

from __future__ import annotations

import math
from xml.sax.saxutils import quoteattr

import numpy as np

from symkin.derive.dh_extraction import numeric_robot, zero_pose_frames
from symkin.robot import Joint, Link, Robot
from symkin.spatial import rpy_from_rotation

VISUAL_RADIUS = 0.02  # metres: a thin rod, readable at arm scale
PRISMATIC_DEFAULT_LIMITS = (-1.0, 1.0)


def _number(value: float) -> str:
    return "0" if abs(value) < 1e-15 else repr(float(value))


def origin_element(pose: np.ndarray) -> str:
    xyz = " ".join(_number(v) for v in pose[:3, 3])
    rpy = " ".join(_number(float(v)) for v in rpy_from_rotation(pose[:3, :3])[:3])
    return f'<origin xyz="{xyz}" rpy="{rpy}"/>'


def joint_element(joint: Joint, index: int, parent: str, child: str, origin: np.ndarray) -> str:
    name = joint.name or f"joint{index}"
    kind = joint.type
    limits = joint.limits
    if kind == "revolute" and limits is None:
        kind = "continuous"
    if kind == "prismatic" and limits is None:
        limits = PRISMATIC_DEFAULT_LIMITS
    lines = [
        f'  <joint name={quoteattr(name)} type="{kind}">',
        f'    <parent link="{parent}"/>',
        f'    <child link="{child}"/>',
        f"    {origin_element(origin)}",
        '    <axis xyz="0 0 1"/>',
    ]
    if limits is not None:
        low, high = (_number(v) for v in limits)
        effort, velocity = (_number(v or 0.0) for v in (joint.max_effort, joint.max_velocity))
        lines.append(
            f'    <limit lower="{low}" upper="{high}" effort="{effort}" velocity="{velocity}"/>'
        )
    return "\n".join([*lines, "  </joint>"])


def inertial_element(link: Link, frame_in_link: np.ndarray) -> str:
    """``<inertial>``: COM and tensor in the robot's link-frame axes, placed by its pose."""
    inertia = [float(v) for v in link.inertia]
    names = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    tensor = " ".join(f'{n}="{_number(v)}"' for n, v in zip(names, inertia, strict=True))
    pose = frame_in_link.copy()
    pose[:3, 3] = frame_in_link[:3, :3] @ np.array([float(c) for c in link.com]) + pose[:3, 3]
    return "\n".join(
        [
            "    <inertial>",
            f"      {origin_element(pose)}",
            f'      <mass value="{_number(float(link.mass))}"/>',
            f"      <inertia {tensor}/>",
            "    </inertial>",
        ]
    )


def visual_element(vector: np.ndarray) -> str:
    """A cylinder from the link origin to ``vector`` (URDF cylinders lie along their z)."""
    length = float(np.linalg.norm(vector))
    if length < 1e-6:
        return ""
    z = vector / length
    axis = np.cross([0.0, 0.0, 1.0], z)
    angle = math.atan2(float(np.linalg.norm(axis)), float(z[2]))
    rotation = np.eye(3)
    if np.linalg.norm(axis) > 1e-12:
        k = axis / np.linalg.norm(axis)
        skew = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        rotation += math.sin(angle) * skew + (1 - math.cos(angle)) * skew @ skew
    elif z[2] < 0:
        rotation = np.diag([1.0, -1.0, -1.0])
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = rotation, vector / 2
    return "\n".join(
        [
            "    <visual>",
            f"      {origin_element(pose)}",
            f'      <geometry><cylinder radius="{VISUAL_RADIUS}" '
            f'length="{_number(length)}"/></geometry>',
            "    </visual>",
        ]
    )


def unmodelled_note(joint: Joint, index: int) -> str:
    """A comment for what URDF cannot hold: motor inertia and friction of a joint."""
    link = joint.link
    if link is None:
        return ""
    items = []
    if link.motor_inertia != 0:
        items.append(
            f"motor inertia {_number(float(link.motor_inertia))} kg m^2 (Pinocchio: armature)"
        )
    if link.coulomb != 0 or link.viscous != 0 or link.coulomb_negative is not None:
        items.append("friction (see the robot file)")
    name = joint.name or f"joint{index}"
    return f"  <!-- {name}: {'; '.join(items)}: not expressible in URDF -->" if items else ""


def link_element(name: str, inertial: str, visual: str) -> str:
    body = "\n".join(part for part in (inertial, visual) if part)
    return f'  <link name="{name}">\n{body}\n  </link>' if body else f'  <link name="{name}"/>'


def urdf_text(source: Robot, header: str) -> str:
    """The URDF document of ``source`` (numeric parameters; module docstring for frames)."""
    robot = numeric_robot(source)
    axes, link_frames, tool = zero_pose_frames(robot)
    frames = [np.eye(4), *axes, tool]  # URDF link frames at q = 0; base_link is the world
    names = ["base_link", *(f"link{i + 1}" for i in range(robot.dof)), "tool"]
    parts = [f"<!-- {line} -->" for line in header.splitlines()]
    if [float(g) for g in robot.gravity] != [0.0, 0.0, -9.81]:
        gravity = ", ".join(_number(float(g)) for g in robot.gravity)
        parts.append(f"<!-- gravity in base_link: ({gravity}) m/s^2; URDF cannot say it -->")
    parts.append(f"<robot name={quoteattr(robot.name)}>")
    for i, name in enumerate(names):
        inertial = ""
        link = robot.joints[i - 1].link if 0 < i <= robot.dof else None
        if link is not None:
            inertial = inertial_element(link, np.linalg.solve(frames[i], link_frames[i]))
        after = frames[i + 1][:3, 3] if i + 1 < len(frames) else frames[i][:3, 3]
        local = np.linalg.solve(frames[i], np.append(after, 1.0))[:3]
        parts.append(link_element(name, inertial, visual_element(local)))
    for i, joint in enumerate(robot.joints):
        origin = np.linalg.solve(frames[i], frames[i + 1])
        parts.append(joint_element(joint, i + 1, names[i], names[i + 1], origin))
        note = unmodelled_note(joint, i + 1)
        parts += [note] if note else []
    tool_origin = origin_element(np.linalg.solve(frames[-2], frames[-1]))
    parts.append(
        f'  <joint name="tool_joint" type="fixed">\n    <parent link="{names[-2]}"/>\n'
        f'    <child link="tool"/>\n    {tool_origin}\n  </joint>'
    )
    return "\n".join([*parts, "</robot>"]) + "\n"

"""Simulated people: one PyBullet multibody per person, built from primitive shapes.

A person is a small URDF written on the fly (so that each shape keeps its own colour):
a pelvis base, torso, head, a ``hair`` link, a separate ``face`` link (eyes, nose, mouth on
the front of the head, so it segments apart from the body), two arms and two two-part legs.
The person frame has x forward (the way the face looks), y to the left and z up; its
origin is the pelvis, between the hips. People are kinematic: they are fixed-base bodies
that the caller moves with :meth:`Person.place` and poses with :meth:`Person.set_pose`.

Segmentation: render with ``flags=pybullet.ER_SEGMENTATION_MASK_OBJECT_AND_LINKINDEX``;
a pixel value ``v >= 0`` holds ``body = v & 0xFFFFFF`` and ``link = (v >> 24) - 1``, and
the eyes, nose and mouth are ``link == person.face_link``, and the whole face (those and
the head's skin around them) is ``link in person.face_links`` (the pelvis is link -1).

This module also holds the tiny URDF builder (:class:`Part`, :func:`link_xml`,
:func:`load_urdf_text`) that ``sim.world`` reuses for furniture and objects.
"""

from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass
from typing import Literal

import pybullet as p

Rgb = tuple[float, float, float]
PoseName = Literal["standing", "sitting", "arms_raised"]
POSES: tuple[PoseName, ...] = ("standing", "sitting", "arms_raised")
Vec3 = tuple[float, float, float]


# --- a minimal URDF builder ------------------------------------------------------------


@dataclass(frozen=True)
class Part:
    """One primitive shape of a link.

    ``size`` is the full extents ``(x, y, z)`` of a box, ``(radius, length)`` of a
    cylinder (along its local z) or ``(radius,)`` of a sphere; ``xyz``/``rpy`` place it in
    the link frame.
    """

    shape: Literal["box", "cylinder", "sphere"]
    size: tuple[float, ...]
    rgb: Rgb
    xyz: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)
    collide: bool = True


def _geometry(part: Part) -> str:
    if part.shape == "box":
        return '<box size="{:.4f} {:.4f} {:.4f}"/>'.format(*part.size)
    if part.shape == "cylinder":
        return '<cylinder radius="{:.4f}" length="{:.4f}"/>'.format(*part.size)
    return f'<sphere radius="{part.size[0]:.4f}"/>'


def link_xml(name: str, parts: list[Part]) -> str:
    """A massless URDF ``<link>`` holding ``parts`` (each visual keeps its own colour)."""
    out = [f'<link name="{name}"><inertial><origin xyz="0 0 0"/><mass value="0"/>'
           '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>']
    for i, part in enumerate(parts):
        origin = '<origin xyz="{:.4f} {:.4f} {:.4f}" rpy="{:.4f} {:.4f} {:.4f}"/>'.format(
            *part.xyz, *part.rpy)
        r, g, b = part.rgb
        out.append(f"<visual>{origin}<geometry>{_geometry(part)}</geometry>"
                   f'<material name="{name}_{i}"><color rgba="{r:.3f} {g:.3f} {b:.3f} 1"/>'
                   "</material></visual>")
        if part.collide:
            out.append(f"<collision>{origin}<geometry>{_geometry(part)}</geometry></collision>")
    out.append("</link>")
    return "".join(out)


def joint_xml(name: str, parent: str, child: str, xyz: Vec3, revolute: bool = False) -> str:
    """A URDF joint: fixed, or revolute about the parent's y axis (pitch)."""
    kind = "revolute" if revolute else "fixed"
    extra = ('<axis xyz="0 1 0"/><limit lower="-3.2" upper="3.2" effort="0" velocity="0"/>'
             if revolute else "")
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/>'
            f'<child link="{child}"/><origin xyz="{xyz[0]:.4f} {xyz[1]:.4f} {xyz[2]:.4f}"/>'
            f"{extra}</joint>")


def load_urdf_text(client: int, name: str, body_xml: str, position: Vec3 = (0, 0, 0),
                   yaw: float = 0.0) -> int:
    """Load a fixed-base body from URDF text (links and joints) and return its id. The text
    is written one element a line: PyBullet's URDF reader rejects very long lines (a cake
    with ten candles makes a line of more than 8 kB)."""
    text = f'<?xml version="1.0"?><robot name="{name}">{body_xml}</robot>'.replace("><", ">\n<")
    fd, path = tempfile.mkstemp(suffix=".urdf")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        return p.loadURDF(path, position, p.getQuaternionFromEuler((0, 0, yaw)),
                          useFixedBase=True, physicsClientId=client)
    finally:
        os.unlink(path)


def build_body(client: int, name: str, parts: list[Part], position: Vec3 = (0, 0, 0),
               yaw: float = 0.0) -> int:
    """Load a single-link static body made of ``parts``."""
    return load_urdf_text(client, name, link_xml("base", parts), position, yaw)


# --- people ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Appearance:
    """What a person looks like: body height and shoulder width (m) and colours (RGB 0-1)."""

    height: float = 1.7
    width: float = 0.45
    shirt: Rgb = (0.2, 0.4, 0.75)
    trousers: Rgb = (0.2, 0.2, 0.25)
    skin: Rgb = (0.87, 0.69, 0.56)
    hair: Rgb = (0.25, 0.16, 0.1)


@dataclass(frozen=True)
class _Dims:
    """Body proportions derived from an :class:`Appearance`."""

    head_r: float
    thigh: float
    shin: float
    leg_r: float
    arm: float
    arm_r: float
    torso_w: float
    torso_d: float
    shoulder_z: float  # shoulder joint height above the hips

    @classmethod
    def of(cls, a: Appearance) -> _Dims:
        h, w = a.height, a.width
        head_r = 0.062 * h
        hip = 0.505 * h
        torso_w = 0.72 * w
        arm_r = 0.1 * w
        return cls(head_r=head_r, thigh=0.245 * h, shin=0.26 * h, leg_r=0.12 * w,
                   arm=0.36 * h, arm_r=arm_r, torso_w=torso_w, torso_d=0.5 * torso_w,
                   shoulder_z=h - 2 * head_r - 0.03 * h - hip - arm_r)


# Joint angles (rad) of each pose: thigh, shin, arm (both sides alike).
_POSE_ANGLES: dict[str, tuple[float, float, float]] = {
    "standing": (0.0, 0.0, 0.0),
    "sitting": (-math.pi / 2, math.pi / 2, -0.45),
    "arms_raised": (0.0, 0.0, -2.9),
}
_SHOE: Rgb = (0.12, 0.1, 0.09)


def _face_parts(r: float, z: float, skin: Rgb) -> list[Part]:
    """Eyes (white with dark pupils), nose and mouth on the front (+x) of a head of radius r."""
    white, pupil, lips = (0.95, 0.95, 0.95), (0.08, 0.06, 0.05), (0.7, 0.2, 0.22)
    nose = (skin[0] * 0.82, skin[1] * 0.75, skin[2] * 0.72)
    parts = []
    for side in (1, -1):
        parts.append(Part("sphere", (0.17 * r,), white, (0.88 * r, side * 0.36 * r, z + 0.2 * r),
                          collide=False))
        parts.append(Part("sphere", (0.09 * r,), pupil, (1.02 * r, side * 0.36 * r, z + 0.2 * r),
                          collide=False))
    parts.append(Part("box", (0.25 * r, 0.16 * r, 0.3 * r), nose, (0.98 * r, 0, z - 0.05 * r),
                      collide=False))
    parts.append(Part("box", (0.16 * r, 0.5 * r, 0.1 * r), lips, (0.9 * r, 0, z - 0.45 * r),
                      collide=False))
    return parts


def _person_xml(a: Appearance, d: _Dims) -> str:
    h, r = a.height, d.head_r
    torso_bottom = 0.06 * h
    torso_top = d.shoulder_z + d.arm_r
    neck_top = torso_top + 0.03 * h
    head_z = neck_top + r
    links = {
        "pelvis": [Part("box", (d.torso_d, d.torso_w, 0.1 * h), a.trousers, (0, 0, 0.02 * h))],
        "torso": [Part("box", (d.torso_d, d.torso_w, torso_top - torso_bottom), a.shirt,
                       (0, 0, (torso_top + torso_bottom) / 2)),
                  Part("cylinder", (0.4 * r, 0.03 * h + 0.02), a.skin,
                       (0, 0, torso_top + 0.015 * h))],
        "head": [Part("sphere", (r,), a.skin, (0, 0, head_z))],
        "hair": [Part("sphere", (1.05 * r,), a.hair, (-0.2 * r, 0, head_z + 0.15 * r),
                      collide=False)],
        "face": _face_parts(r, head_z, a.skin),
    }
    sleeve, fore = 0.55 * d.arm, 0.45 * d.arm
    arm = [Part("cylinder", (d.arm_r, sleeve), a.shirt, (0, 0, -sleeve / 2)),
           Part("cylinder", (0.8 * d.arm_r, fore), a.skin, (0, 0, -sleeve - fore / 2)),
           Part("sphere", (1.1 * d.arm_r,), a.skin, (0, 0, -d.arm), collide=False)]
    thigh = [Part("cylinder", (d.leg_r, d.thigh), a.trousers, (0, 0, -d.thigh / 2))]
    shoe_h = 0.06
    shin = [Part("cylinder", (0.9 * d.leg_r, d.shin - shoe_h), a.trousers,
                 (0, 0, -(d.shin - shoe_h) / 2)),
            Part("box", (2.6 * d.leg_r, 1.8 * d.leg_r, shoe_h), _SHOE,
                 (0.5 * d.leg_r, 0, -d.shin + shoe_h / 2))]
    for side in ("l", "r"):
        links[f"arm_{side}"] = arm
        links[f"thigh_{side}"] = thigh
        links[f"shin_{side}"] = shin
    arm_y = d.torso_w / 2 + d.arm_r + 0.005
    leg_y = d.torso_w / 4
    joints = [joint_xml("torso_joint", "pelvis", "torso", (0, 0, 0)),
              joint_xml("head_joint", "torso", "head", (0, 0, 0)),
              joint_xml("hair_joint", "head", "hair", (0, 0, 0)),
              joint_xml("face_joint", "head", "face", (0, 0, 0))]
    for side, s in (("l", 1), ("r", -1)):
        joints += [joint_xml(f"shoulder_{side}", "torso", f"arm_{side}",
                             (0, s * arm_y, d.shoulder_z), revolute=True),
                   joint_xml(f"hip_{side}", "pelvis", f"thigh_{side}", (0, s * leg_y, 0),
                             revolute=True),
                   joint_xml(f"knee_{side}", f"thigh_{side}", f"shin_{side}", (0, 0, -d.thigh),
                             revolute=True)]
    return "".join(link_xml(n, parts) for n, parts in links.items()) + "".join(joints)


class Person:
    """A person in a PyBullet world (see :func:`create_person`)."""

    def __init__(self, client: int, appearance: Appearance | None = None, x: float = 0.0,
                 y: float = 0.0, yaw: float = 0.0, pose: PoseName = "standing",
                 name: str = "person") -> None:
        self.client = client
        self.name = name
        self.appearance = appearance or Appearance()
        self._dims = _Dims.of(self.appearance)
        self.urdf = _person_xml(self.appearance, self._dims)   # the body, for copies of the world
        self.body_id = load_urdf_text(client, name, self.urdf)
        #: link name -> link index (pelvis is the base, -1)
        self.links = {p.getJointInfo(self.body_id, j, physicsClientId=client)[12].decode(): j
                      for j in range(p.getNumJoints(self.body_id, physicsClientId=client))}
        self.links["pelvis"] = -1
        self.x, self.y, self.yaw = x, y, yaw
        self.pose: PoseName = pose
        self.set_pose(pose)

    @property
    def face_link(self) -> int:
        """Link index of the face (eyes, nose, mouth) for segmentation masks."""
        return self.links["face"]

    @property
    def face_links(self) -> tuple[int, int]:
        """Link indices of the whole face seen from the front: the head's skin (the hair is a
        link of its own) and the eyes, nose and mouth."""
        return self.links["head"], self.links["face"]

    def _hip_height(self) -> float:
        d = self._dims
        return d.shin + d.leg_r if self.pose == "sitting" else d.thigh + d.shin

    def _set_angles(self, **angles: float) -> None:
        for link, angle in angles.items():
            p.resetJointState(self.body_id, self.links[link], angle, physicsClientId=self.client)

    def set_pose(self, pose: PoseName) -> None:
        """Change the posture: ``standing``, ``sitting`` or ``arms_raised``."""
        if pose not in _POSE_ANGLES:
            raise ValueError(f"unknown pose {pose!r}; expected one of {POSES}")
        self.pose = pose
        thigh, shin, arm = _POSE_ANGLES[pose]
        self._set_angles(thigh_l=thigh, thigh_r=thigh, shin_l=shin, shin_r=shin,
                         arm_l=arm, arm_r=arm)
        self.place(self.x, self.y, self.yaw)

    def set_gait(self, phase: float) -> None:
        """Swing legs and arms for a walking step at ``phase`` (rad); only when standing."""
        if self.pose != "standing":
            return
        swing, knee = 0.35 * math.sin(phase), 0.15 * (1 - math.cos(phase))
        self._set_angles(thigh_l=swing, thigh_r=-swing, shin_l=knee, shin_r=knee,
                         arm_l=-swing, arm_r=swing)

    def place(self, x: float, y: float, yaw: float) -> None:
        """Put the person at floor position ``(x, y)`` facing ``yaw`` (rad, 0 = +x)."""
        self.x, self.y, self.yaw = x, y, yaw
        p.resetBasePositionAndOrientation(
            self.body_id, (x, y, self._hip_height()), p.getQuaternionFromEuler((0, 0, yaw)),
            physicsClientId=self.client)

    def aabb(self) -> tuple[Vec3, Vec3]:
        """World-axis bounding box ``(min, max)`` of the body (face and hair excluded)."""
        boxes = [p.getAABB(self.body_id, link, physicsClientId=self.client)
                 for name, link in self.links.items() if name not in ("face", "hair")]
        return (tuple(min(b[0][i] for b in boxes) for i in range(3)),  # type: ignore[return-value]
                tuple(max(b[1][i] for b in boxes) for i in range(3)))

    def remove(self) -> None:
        """Delete the person's body from the simulation."""
        p.removeBody(self.body_id, physicsClientId=self.client)
        self.body_id = -1


def create_person(client: int, appearance: Appearance | None = None, x: float = 0.0,
                  y: float = 0.0, yaw: float = 0.0, pose: PoseName = "standing",
                  name: str = "person") -> Person:
    """Build a person in ``client`` at floor position ``(x, y)`` facing ``yaw`` (rad)."""
    return Person(client, appearance, x, y, yaw, pose, name)

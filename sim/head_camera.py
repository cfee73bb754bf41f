"""The simulated forehead camera: colour, depth and segmentation frames rendered from the
camera link's pose (TinyRenderer here, or bands shared with a helper process:
sim/split_render.py), with the faults a run can inject (docs/reliability.md)."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from functools import partial
from typing import Any

import numpy as np
import pybullet as p

from robot.body import CameraConfig
from sim.render import Buffers, tiny_render


def decode_segmentation(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split a mask rendered with ``ER_SEGMENTATION_MASK_OBJECT_AND_LINKINDEX`` into body
    ids and link indices (the base is link -1; background is body -1, link -1)."""
    mask = np.asarray(mask, dtype=np.int64)
    background = mask < 0
    bodies = np.where(background, -1, mask & ((1 << 24) - 1))
    links = np.where(background, -1, (mask >> 24) - 1)
    return bodies, links


class SimCamera:
    """The camera on link ``link`` of the robot body ``body`` (:class:`robot.body.Camera`);
    ``faces`` tells the expression on the face of a body the camera sees (the world's)."""

    def __init__(self, client: int, body: int, link: int, cfg: CameraConfig,
                 faces: Callable[[int], str | None]) -> None:
        self.client, self.body, self.link, self.cfg = client, body, link, cfg
        self._faces = faces
        self._light: dict[str, Any] = {}
        #: draws the frames: TinyRenderer here, or a
        #: :class:`~sim.split_render.SplitRenderer` sharing the work with a helper process
        self.renderer: Callable[..., Buffers] = partial(tiny_render, client)
        self._fault: str | None = None
        self._last_render: dict[tuple[int, int], tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        self.frame_seq = 0   # sequence number of the frames (a frozen camera repeats)

    def pose(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """World position, optical axis (unit) and image-up vector of the head camera."""
        state = p.getLinkState(self.body, self.link,
                               computeForwardKinematics=True, physicsClientId=self.client)
        rot = np.array(p.getMatrixFromQuaternion(state[5], physicsClientId=self.client))
        rot = rot.reshape(3, 3)
        return np.array(state[4]), rot[:, 0], rot[:, 2]

    def heading(self) -> float:
        """Where the head faces on the floor (rad, world frame): its camera's axis."""
        axis = self.pose()[1]
        return math.atan2(float(axis[1]), float(axis[0]))

    def matrices(self, width: int, height: int) -> tuple[list[float], list[float]]:
        """The head camera's OpenGL view and projection matrices (column-major) for a
        ``width`` x ``height`` frame, as ``getCameraImage`` takes them."""
        eye, forward, up = self.pose()
        cam = self.cfg
        view = p.computeViewMatrix(eye.tolist(), (eye + forward).tolist(), up.tolist(),
                                   physicsClientId=self.client)
        proj = p.computeProjectionMatrixFOV(cam.fov_deg, width / height, cam.near, cam.far,
                                            physicsClientId=self.client)
        return view, proj

    def body_at_pixel(self, u: float, v: float, width: int, height: int) -> int | None:
        """The body the head camera sees at pixel ``(u, v)`` of a ``width`` x ``height``
        frame: a ray cast along that pixel's line of sight (None: nothing, or the robot)."""
        eye, forward, up = self.pose()
        half = math.tan(math.radians(self.cfg.fov_deg) / 2)
        x = (2 * (u + 0.5) / width - 1) * half * width / height
        y = (1 - 2 * (v + 0.5) / height) * half
        ray = forward + x * np.cross(forward, up) + y * up
        ray /= np.linalg.norm(ray)
        hit = p.rayTest((eye + 0.05 * ray).tolist(), (eye + self.cfg.far * ray).tolist(),
                        physicsClientId=self.client)[0][0]
        return hit if hit >= 0 and hit != self.body else None

    def expression_at(self, u: float, v: float, width: int, height: int) -> str | None:
        """The expression on the face of the body seen at pixel ``(u, v)``: what an
        expression classifier would read off a face the detector found there."""
        body = self.body_at_pixel(u, v, width, height)
        return self._faces(body) if body is not None else None

    def _render(self, width: int, height: int, flags: int
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        cam = self.cfg
        view, proj = self.matrices(width, height)
        rgba, z, seg = self.renderer(width, height, view, proj, flags, self._light)
        rgb = rgba[..., :3].copy()
        # OpenGL depth buffer in [0, 1] -> distance along the optical axis (m)
        depth = cam.far * cam.near / (cam.far - (cam.far - cam.near) * z)
        if self._fault == "black":
            rgb[:] = 0
        self.frame_seq += 1
        render = (rgb, seg, depth)
        self._last_render[width, height] = render
        return render

    def _frame(self, width: int, height: int, flags: int
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A new render, or the last one again while the camera is frozen."""
        if self._fault == "frozen" and (width, height) in self._last_render:
            return self._last_render[width, height]
        return self._render(width, height, flags)

    def set_fault(self, mode: str | None) -> None:
        """``"black"``: black colour frames; ``"frozen"``: the last frame again, with its
        sequence number (:attr:`frame_seq`); None: the camera works."""
        self._fault = mode

    def set_lighting(self, light: Mapping[str, Any]) -> None:
        """TinyRenderer lighting for the camera: keyword arguments of ``getCameraImage``
        such as ``lightDirection`` or ``shadow`` (e.g. the world's
        ``Light.camera_kwargs()``); an empty mapping restores PyBullet's defaults."""
        self._light = dict(light)

    def frame(self, width: int = 320, height: int = 240) -> np.ndarray:
        """RGB image (height, width, 3) uint8 from the head camera (TinyRenderer)."""
        return self._frame(width, height, p.ER_NO_SEGMENTATION_MASK)[0]

    def frame_with_depth(self, width: int = 320, height: int = 240,
                                ) -> tuple[np.ndarray, np.ndarray]:
        """RGB image and the (height, width) float32 depth image of the same view: each
        pixel's distance along the optical axis in metres (Pepper's 3D camera; the same
        render, so it costs nothing extra)."""
        rgb, _, depth = self._frame(width, height, p.ER_NO_SEGMENTATION_MASK)
        return rgb, depth

    def frame_with_segmentation(self, width: int = 320, height: int = 240,
                                       ) -> tuple[np.ndarray, np.ndarray]:
        """RGB image and the (height, width) int32 segmentation mask. Each mask value is
        ``body_id + ((link_index + 1) << 24)``, -1 for background; see
        :func:`decode_segmentation`."""
        return self._frame(width, height, p.ER_SEGMENTATION_MASK_OBJECT_AND_LINKINDEX)[:2]

"""The household world's lighting (sim/world.py hands it to the renderer)."""

from __future__ import annotations

from dataclasses import dataclass

from sim.people import Rgb


@dataclass(frozen=True)
class Light:
    """TinyRenderer lighting; pass ``**light.camera_kwargs()`` to ``getCameraImage``."""

    direction: tuple[float, float, float]
    colour: Rgb
    ambient: float
    diffuse: float
    specular: float
    shadows: bool

    def camera_kwargs(self) -> dict[str, object]:
        """Keyword arguments for ``pybullet.getCameraImage``."""
        return {"lightDirection": list(self.direction), "lightColor": list(self.colour),
                "lightAmbientCoeff": self.ambient, "lightDiffuseCoeff": self.diffuse,
                "lightSpecularCoeff": self.specular, "shadow": int(self.shadows)}

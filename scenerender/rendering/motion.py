"""What changes over the animation, which decides the passes that can be cached.

A shadow map depends on its light's placement and the shadow casters; a directional
light's also on the camera, since its view is fitted to the receivers the camera sees
(world.shadows). Everything drawn from the camera depends on all of it.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Motion:
    geometry_static: bool   # no object moves, scales, appears or disappears
    camera_static: bool
    everything_static: bool  # not even a colour changes: every frame is the same image

    def shadow_static(self, light) -> bool:
        """The light's shadow map can be rendered once for the whole animation."""
        if (light.attach_camera or light.kind == "directional") and not self.camera_static:
            return False
        moves = light.moves() if not light.attach_camera else False
        return self.geometry_static and not moves


def _camera_static(spec) -> bool:
    if spec is None:
        return True  # framed once from the scene's bounds at t = 0
    tracks = [spec.position, spec.target, spec.yaw, spec.pitch, spec.fov, spec.height]
    return all(t is None or t.is_constant for t in tracks)


def _lights_static(lights) -> bool:
    for light in lights:
        tracks = [light.color, light.intensity, light.enabled, light.position, light.direction,
                  light.inner_angle, light.outer_angle]
        if not all(t is None or t.is_constant for t in tracks):
            return False
    return True


def analyse(world) -> Motion:
    render = world.render
    geometry = all(obj.is_static for obj in world.objects)
    camera = _camera_static(world.spec.camera)
    looks = (render.background.is_constant
             and (render.fog is None or (render.fog.color.is_constant and render.fog.density.is_constant))
             and all(m.is_static for m in world.materials())
             and all(obj.outline is None or obj.outline.color.is_constant for obj in world.objects))
    everything = geometry and camera and looks and _lights_static(world.lights)
    return Motion(geometry_static=geometry, camera_static=camera, everything_static=everything)

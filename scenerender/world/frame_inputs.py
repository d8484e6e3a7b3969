"""What the world hands each frame, and which of it changes over the animation.

The render graph imports each of these as an input (``rendering.inputs``); a pass is
cached across frames exactly when everything it reads is static. Whether an input is
dynamic is worked out here from the scene's tracks, by looking through the input's whole
definition for a Track that changes (``animation.animated_keys``): nothing lists the
animatable keys, so a key added to the format later is covered without being listed.

Where one input is computed from another, the dependency is written here once:
- the camera's automatic near/far planes fit the scene's bounds, so they follow the objects;
- a light attached to the camera follows the camera;
- a shadow map's views fit the scene's bounds, and a directional light's also the part of
  the scene the camera sees, unless its view stays put for the run (world.directional_views);
- the packed light data holds every light and shadow view, camera-relative, so it follows
  them all, and the camera wherever it holds a position or a view.
"""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.animation import animated_keys
from scenerender.world.motion import blurs_by_velocity

# A light's keys that change how much light it gives but not where it points or from where
# (a shadow map does not depend on them). Every other key counts as placement, so a key
# added later makes shadow maps dynamic, never stale.
LIGHT_APPEARANCE_KEYS = ("color", "intensity", "enabled", "inner_angle", "attenuation")

# An object's keys that are inputs of their own.
OBJECT_LOOK_KEYS = ("materials", "outline")


@dataclass(frozen=True)
class WorldInput:
    """One per-frame input.

    name:     its name in graph dumps ("camera", "light:sun", "shadow_views:sun", "lights"...).
    dynamic:  True when it can change over the animation.
    because:  why it is dynamic: the animated key paths, or the input it follows.
    """

    name: str
    dynamic: bool
    because: tuple = ()

    def describe(self) -> str:
        if not self.dynamic:
            return ""
        shown = ", ".join(self.because[:3])
        return shown + (f" and {len(self.because) - 3} more" if len(self.because) > 3 else "")


@dataclass(frozen=True)
class WorldInputs:
    """Every input a scene has. ``per_light`` has one per light of ``world.lights``, same
    index; ``ambient`` is the ambient lights' sum; ``shadow_views`` has one entry per
    shadowed light, keyed by its index. ``lights`` is all of those lights and views packed
    as the lighting shaders read them (rendering.lights): it changes when any of them
    does, and with the camera, since positions and views are packed camera-relative.
    ``exposure`` is there only where ``render.exposure`` scales the image (has_exposure)."""

    camera: WorldInput
    objects: WorldInput
    materials: WorldInput
    background: WorldInput
    per_light: tuple
    ambient: WorldInput
    shadow_views: dict
    lights: WorldInput
    fog: WorldInput | None
    outlines: WorldInput | None
    skybox: WorldInput | None
    exposure: WorldInput | None
    environment: WorldInput | None = None      # intensity, colour and rotation of the environment light
    environment_map: WorldInput | None = None  # its image and diffuse map on the GPU: static
    lens: WorldInput | None = None  # the thin lens's radius and focus, for render.depth_of_field: gather
    environment_views: WorldInput | None = None  # its visibility maps' views: follow the objects and its rotation
    motion: WorldInput | None = None  # the objects' and camera's motion over the shutter, for render.motion_blur: velocity

    def all(self) -> list[WorldInput]:
        fixed = [self.camera, self.objects, self.materials, self.background, *self.per_light, self.ambient,
                 *self.shadow_views.values(), self.lights]
        return fixed + [i for i in (self.fog, self.outlines, self.skybox, self.exposure, self.environment,
                                    self.environment_map, self.lens,
                                    self.environment_views, self.motion) if i is not None]


def _input(name: str, keys: list, follows: tuple = ()) -> WorldInput:
    because = tuple(keys) + tuple(f"follows {i.name}" for i in follows if i.dynamic)
    return WorldInput(name, bool(because), because)


@dataclass(frozen=True)
class AnimatedParts:
    """The animated keys of a world's objects and materials.

    per_object: one tuple of key paths ("position", "instances.rotation") per object of
                ``world.objects``, same index; empty for an object that never moves.
    materials:  the animated key paths of the materials, by name ("steel.diffuse").

    Looking through every object is most of what working out the inputs costs in a scene
    of many objects (0.06 s for 1,000 spheres), and three users share it: the inputs with
    and without fixed views, and the frames' still objects (world.frame). World.animated_parts
    keeps it."""

    per_object: tuple
    materials: tuple


def animated_parts(world) -> AnimatedParts:
    """Look through ``world``'s objects (their materials and outlines apart) and materials."""
    return AnimatedParts(tuple(tuple(animated_keys(obj, skip=OBJECT_LOOK_KEYS)) for obj in world.objects),
                         tuple(f"{m.name}.{key}" for m in world.materials() for key in animated_keys(m)))


def world_inputs(world) -> WorldInputs:
    """The inputs of ``world`` (a world.build.World) with their static/dynamic state;
    ``World.inputs`` keeps them."""
    return _world_inputs(world, frozenset(world.fixed_shadow_sizes))


def camera_fitted_inputs(world) -> WorldInputs:
    """The inputs as they would be with every directional light's view following the
    camera: what decides which views may stay put (world.directional_views)."""
    return _world_inputs(world, frozenset())


def whole_footprint(world) -> bool:
    """Whether every directional light's view covers its casters' whole footprint in every
    frame, never only what the camera sees: with render.indirect, whose probes see all of
    the scene (world.directional_views)."""
    return world.settings.indirect is not None


def _world_inputs(world, fixed_views: frozenset) -> WorldInputs:
    """fixed_views: indices in ``world.lights`` of directional lights whose view stays put."""
    spec, render = world.spec, world.render
    parts = world.animated_parts
    objects = _input("objects", [f"{obj.name}.{key}" for obj, keys in zip(world.objects, parts.per_object)
                                 for key in keys])
    auto_planes = spec.camera is None or "auto" in (spec.camera.near, spec.camera.far)
    # an aperture filmed by sub-frames moves the eye over the lens every sub-frame (world.lens)
    has_lens = spec.camera is not None and spec.camera.aperture is not None
    gather = has_lens and render.depth_of_field == "gather"
    lens = ["camera.aperture"] if has_lens and not gather else []
    file_camera = [f"camera.from.{key}" for key in animated_keys(world.file_camera)]
    camera = _input("camera", animated_keys(spec.camera) + file_camera + lens, (objects,) if auto_planes else ())
    per_light, views = [], {}
    for index, (light, name) in enumerate(zip(world.lights, _unique_names(world.lights))):
        per_light.append(_input(f"light:{name}", animated_keys(light), (camera,) if light.attach_camera else ()))
        if light.shadow is not None:
            follows_camera = ((light.kind == "directional" and index not in fixed_views and not whole_footprint(world))
                              or light.attach_camera)
            fitted_to = (objects, camera) if follows_camera else (objects,)
            views[index] = _input(f"shadow_views:{name}", animated_keys(light, skip=LIGHT_APPEARANCE_KEYS), fitted_to)
    ambient_keys = [f"{name}.{key}" for light, name in zip(world.ambient, _unique_names(world.ambient))
                    for key in animated_keys(light)]
    # the packed lights: every light's own keys, its shadow views, and the camera where a
    # light has a position or views (packed relative to the camera)
    light_keys = [f"{name}.{key}" for light, name in zip(world.lights, _unique_names(world.lights))
                  for key in animated_keys(light)]
    placed = bool(views) or any(light.kind != "directional" or light.attach_camera for light in world.lights)
    lights = _input("lights", light_keys, (*views.values(), *((camera,) if placed else ())))
    outlined = [obj for obj in world.objects if obj.outline is not None]
    return WorldInputs(
        # the gather blur's lens: its radius and focus follow the camera (fov, target) and the objects (focus)
        lens=_input("lens", ["camera.focus_distance"] if animated_keys(spec.camera.focus_distance) else [],
                    (camera, objects)) if gather else None,
        # the velocity blur's motion: it follows the camera and the objects (world.motion)
        motion=_input("motion", [], (camera, objects)) if blurs_by_velocity(world) else None,
        camera=camera, objects=objects,
        materials=_input("materials", list(parts.materials)),
        background=_input("background", animated_keys(render.background)),
        per_light=tuple(per_light), ambient=_input("ambient", ambient_keys), shadow_views=views, lights=lights,
        fog=_input("fog", animated_keys(render.fog)) if render.fog is not None else None,
        outlines=_input("outlines", [f"{o.name}.outline.{k}" for o in outlined for k in animated_keys(o.outline)])
        if outlined else None,
        skybox=_input("skybox", []) if render.skybox is not None else None,
        exposure=_input("exposure", ["render.exposure"] if animated_keys(render.exposure) else [])
        if has_exposure(render) else None,
        **_environment_inputs(world.environment, objects),
    )


def _environment_inputs(environment, objects: WorldInput) -> dict:
    """The environment light's inputs: its per-frame values, animated by its keys; its
    images, which never change (so what is computed from them alone is cached); and where
    the scene blocks its light, the views of its visibility maps, fitted to the objects and
    turned with its rotation (not with its colour or intensity)."""
    if environment is None:
        return {}
    keys = [f"{environment.name}.{key}" for key in animated_keys(environment)]
    found = {"environment": _input("environment", keys), "environment_map": _input("environment_map", [])}
    if environment.visibility:
        placement = [f"{environment.name}.{key}" for key in animated_keys(environment, skip=LIGHT_APPEARANCE_KEYS)]
        found["environment_views"] = _input("environment_views", placement, (objects,))
    return found


def has_exposure(render) -> bool:
    """Whether ``render.exposure`` (a ``scene.model.render.RenderSpec``'s) ever scales the
    image: it is animated, or a constant other than 0 stops. At 0 throughout, the output
    shaders leave the multiply out."""
    return bool(animated_keys(render.exposure)) or render.exposure(0.0) != 0.0


def _unique_names(lights) -> list[str]:
    """Light names, with a suffix where two lights share one."""
    names, seen = [], {}
    for light in lights:
        seen[light.name] = seen.get(light.name, 0) + 1
        names.append(light.name if seen[light.name] == 1 else f"{light.name}({seen[light.name]})")
    return names


def redrawn_shadow_maps(world) -> frozenset:
    """Indices in ``world.lights`` of the shadowed lights whose views change during the
    run (their maps are redrawn every frame)."""
    return frozenset(index for index, views in world.inputs.shadow_views.items() if views.dynamic)

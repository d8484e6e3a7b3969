"""Directional shadow views that stay put for the run (world.directional_views): chosen only
where nothing but the camera moves, and only at a size whose texels are no coarser than
the camera-following view's in any frame."""
from __future__ import annotations

import numpy as np
import pytest

import scenerender
from scenerender.world.directional_views import MAX_GROWTH
from scenerender.world.frame import FrameEvaluator
from scenerender.world.shadows import directional_half_width, directional_rotation, visible_region
from scenerender.world.transforms import union_bounds

from conftest import SCENES


def _world(path=SCENES / "showcase.yaml", overrides=()):
    return scenerender.load(path, list(overrides)).world


def test_the_showcase_sun_stays_put_at_a_size_no_coarser_than_following_the_camera_in_any_frame():
    """Judged on 24 frames, checked here on all 120: the fixed map's texel (the whole
    footprint over its size) is never larger than the camera-following one's."""
    world = _world()
    sizes = world.fixed_shadow_sizes
    assert list(sizes) == [0]  # the sun; the lantern is a point light
    asked = world.lights[0].shadow.size
    assert asked < sizes[0] <= MAX_GROWTH * asked
    evaluator = FrameEvaluator(world, world.settings.size, None)
    rotation = directional_rotation(np.asarray(world.lights[0].direction(0.0), dtype=np.float64))
    frames = [evaluator.evaluate(i, i / world.output.fps) for i in range(world.output.frame_count)]
    casters = union_bounds([f.bounds for obj, f in zip(world.objects, frames[0].objects) if obj.cast_shadows])
    whole_texel = 2 * directional_half_width(rotation, casters, None) / sizes[0]
    followed_texels = [2 * directional_half_width(rotation, casters, visible_region(f.camera, f.bounds)) / asked
                       for f in frames]
    assert whole_texel <= min(followed_texels)
    assert whole_texel > 0.9 * min(followed_texels)  # and not needlessly large


@pytest.mark.parametrize("overrides, why", [
    (["objects[9].instances[0].position=[60, 0, 0]"], "a pine 60 m out: the fixed map would need over 2x"),
    (["objects[4].position={keys: [[0, [0.3, 0.42, 1.0]], [4, [1.3, 0.42, 1.0]]]}"], "the fox moves"),
    (["lights[0].direction={keys: [[0, [0.45, -0.55, 0.7]], [4, [0.5, -0.5, 0.7]]]}"], "the sun turns"),
    (["camera.position=[0, 2.9, 7.5]"], "a still camera: its fitted view never changes anyway"),
    (["output.duration=0.03"], "one frame: every map is drawn once anyway"),
    (["lights[0].shadows={size: 8192}"], "a fixed map would pass 8192 px"),
])
def test_the_sun_follows_the_camera_where_a_fixed_map_does_not_pay(overrides, why):
    assert _world(overrides=overrides).fixed_shadow_sizes == {}, why


def test_a_fixed_view_is_static_in_the_graph_and_sized_in_the_atlas():
    from scenerender.rendering.renderer import plan

    world = _world()
    showcase = plan(world, world.settings.size, world.settings.samples)
    size = world.fixed_shadow_sizes[0]
    assert showcase.atlas.tiles[0][0].size == size
    sun = next(n.render_pass for n in showcase.compiled.passes if n.render_pass.name == "shadow:sun")
    assert showcase.compiled.is_static(sun) and f"{size}px" in sun.describe()

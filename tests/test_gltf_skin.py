"""Skinned and morphed glTF meshes playing a clip: JOINTS_0 / WEIGHTS_0 and
inverseBindMatrices, morph targets and their animated weights, posed on the GPU by
transform feedback (shaders/mesh/deform.vert) before the frame's passes run. The posed
vertices, read back from the GPU, equal a CPU skinning and morphing of the same inputs."""
from __future__ import annotations

import math

import numpy as np
import pytest

import scenerender
from conftest import scene
from gltf_files import GlbBuilder

pytestmark = pytest.mark.gl

BEND = 90.0  # degrees the upper joint turns about z in the clip's first second


def _column(segments: int = 8):
    """A 0.2 x 2 x 0.2 column along +Y, in rings: positions (N, 3), normals, faces, and
    joints / weights: the lower half follows joint 0, the upper joint 1, blended about y = 1."""
    rings = []
    for k in range(segments + 1):
        y = 2.0 * k / segments
        rings.append([[-0.1, y, -0.1], [0.1, y, -0.1], [0.1, y, 0.1], [-0.1, y, 0.1]])
    positions = np.array(rings, dtype=np.float64).reshape(-1, 3)
    normals = positions * [1, 0, 1]
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    faces = []
    for k in range(segments):
        for side in range(4):
            a, b = 4 * k + side, 4 * k + (side + 1) % 4
            faces += [[a, a + 4, b], [b, a + 4, b + 4]]
    upper = np.clip((positions[:, 1] - 0.75) / 0.5, 0.0, 1.0)
    joints = np.tile([0, 1, 0, 0], (len(positions), 1))
    weights = np.stack([1.0 - upper, upper, np.zeros_like(upper), np.zeros_like(upper)], axis=1)
    return positions, normals, np.array(faces), joints, weights


def _targets():
    """Two morph targets of the column: (2, N, 3) position and normal deltas."""
    positions, normals, _, _, _ = _column()
    widen = positions * [0.5, 0.0, 0.0]
    stretch = np.stack([np.zeros(len(positions)), positions[:, 1] * 0.3, positions[:, 0]], axis=1)
    turn = np.stack([np.zeros(len(normals)), np.full(len(normals), 0.4), np.zeros(len(normals))], axis=1)
    return np.stack([widen, stretch]), np.stack([np.zeros_like(turn), turn])


MORPH_KEYS = np.array([[0.0, 0.0], [1.0, 0.5]])  # the targets' weights at t = 0 and 1


def _skinned_glb(path, skinned: bool = True, morphed: bool = False):
    positions, normals, faces, joints, weights = _column()
    builder = GlbBuilder()
    attributes = {"POSITION": builder.accessor(positions, "VEC3"), "NORMAL": builder.accessor(normals, "VEC3")}
    if skinned:
        attributes.update(JOINTS_0=builder.accessor(joints, "VEC4", 5123), WEIGHTS_0=builder.accessor(weights, "VEC4"))
    primitive = {"attributes": attributes,
                 "indices": builder.accessor(faces.reshape(-1), "SCALAR", 5125, target=34963)}
    if morphed:
        moved, turned = _targets()
        primitive["targets"] = [{"POSITION": builder.accessor(moved[t], "VEC3"),
                                 "NORMAL": builder.accessor(turned[t], "VEC3")} for t in range(2)]
    mesh = builder.mesh(primitive)
    upper = builder.node(root=False, name="upper", translation=[0, 1, 0])
    root = builder.node(name="root", children=[upper])
    binds = np.stack([np.eye(4), np.linalg.inv(_translation(0, 1, 0))])
    ibm = builder.accessor(binds.transpose(0, 2, 1).reshape(-1, 16), "MAT4", target=None)
    builder.json["skins"] = [{"joints": [root, upper], "inverseBindMatrices": ibm}]
    # the node holding the mesh is far away: a skinned mesh ignores its node's transform
    column = builder.node(mesh, name="column", translation=[50, 0, 0] if skinned else [2, 0, 0],
                          **({"skin": 0} if skinned else {}))
    quarter = [0.0, 0.0, math.sin(math.radians(BEND) / 2), math.cos(math.radians(BEND) / 2)]
    channels = [(upper, "rotation", [0.0, 1.0], [[0, 0, 0, 1], quarter], "LINEAR")]
    if morphed:
        channels.append((column, "weights", [0.0, 1.0], MORPH_KEYS.reshape(-1), "LINEAR"))
    builder.animation("bend", channels)
    return builder.write(path)


def _translation(x, y, z):
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def _rotation_z(degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    m = np.eye(4)
    m[:2, :2] = [[c, -s], [s, c]]
    return m


def cpu_morphing(t: float) -> tuple[np.ndarray, np.ndarray]:
    """The column's positions and unit normals at clip time t, morphed here: v + sum_i m_i dv_i."""
    positions, normals, _, _, _ = _column()
    u = min(t, 1.0)
    m = (1 - u) * MORPH_KEYS[0] + u * MORPH_KEYS[1]
    moved, turned = _targets()
    normals = normals + np.tensordot(m, turned, axes=1)
    return positions + np.tensordot(m, moved, axes=1), normals / np.linalg.norm(normals, axis=1, keepdims=True)


def cpu_skinning(t: float, positions: np.ndarray | None = None) -> np.ndarray:
    """The column's vertices (or ``positions``) at clip time t, skinned here: sum_k w_k W_k IBM_k v."""
    rest, _, _, joints, weights = _column()
    positions = rest if positions is None else positions
    worlds = [np.eye(4), _translation(0, 1, 0) @ _rotation_z(BEND * min(t, 1.0))]
    binds = [np.eye(4), np.linalg.inv(_translation(0, 1, 0))]
    palette = [w @ b for w, b in zip(worlds, binds)]
    homogeneous = np.hstack([positions, np.ones((len(positions), 1))])
    out = np.zeros((len(positions), 4))
    for k in range(4):
        matrices = np.stack([palette[j] for j in joints[:, k]])
        out += weights[:, k:k + 1] * np.einsum("nij,nj->ni", matrices, homogeneous)
    return out[:, :3]


SCENE = """
render: {size: [64, 64], samples: 1}
output: {frames: 5, fps: 4}
camera: {position: [0, 1.2, 5], target: [0, 1, 0], fov: 50}
objects:
  - mesh: arm.glb
    ANIMATION
"""


@pytest.mark.parametrize("frame", [0, 1, 2, 4])
def test_gpu_skinned_vertices_equal_a_cpu_skinning(gl, tmp_path, frame):
    _skinned_glb(tmp_path / "arm.glb")
    with scenerender.Renderer(scene(SCENE.replace("ANIMATION", "animation: {clip: bend, loop: false}"), base_dir=tmp_path),
                              gl=gl) as renderer:
        renderer.render(frame)
        skin = next(iter(renderer._renderer.scene.deforms.values()))
        vertices = np.frombuffer(skin.mesh.vertices.read(), dtype=np.float32).reshape(-1, 8)
    expected = cpu_skinning(frame / 4.0)
    assert np.abs(vertices[:, :3] - expected).max() < 1e-4
    # the normals turned with them: unit length, and the top ring's faces the bend's way
    assert np.allclose(np.linalg.norm(vertices[:, 3:6], axis=1), 1.0, atol=1e-5)


def test_a_skinned_part_moves_and_its_bounds_follow(gl, tmp_path):
    _skinned_glb(tmp_path / "arm.glb")
    loaded = scene(SCENE.replace("ANIMATION", "animation: {clip: bend, loop: false}"), base_dir=tmp_path)
    part = loaded.world.objects[0]
    bent = part.local_bounds(1.0)
    tip = cpu_skinning(1.0)
    assert np.all(bent[0] <= tip.min(axis=0) + 1e-9) and np.all(bent[1] >= tip.max(axis=0) - 1e-9)
    assert bent[0][0] < -0.5  # bent over towards -x, outside the rest column's bounds
    rest = scenerender.render(loaded, frames=[0])
    assert not np.array_equal(next(rest).pixels, next(scenerender.render(loaded, frames=[4])).pixels)


def test_without_a_clip_the_file_renders_as_before(gl, tmp_path):
    """No ``animation`` key: the mesh node's own transform places it (x = 50, off screen)
    and nothing is skinned, as scenerender drew such files before."""
    _skinned_glb(tmp_path / "arm.glb")
    loaded = scene(SCENE.replace("ANIMATION", ""), base_dir=tmp_path)
    assert loaded.world.objects[0].deform is None
    assert loaded.world.objects[0].mesh.bounds()[0][0] > 49.0


def _posed(gl, tmp_path, frame: int) -> np.ndarray:
    with scenerender.Renderer(scene(SCENE.replace("ANIMATION", "animation: {clip: bend, loop: false}"),
                                    base_dir=tmp_path), gl=gl) as renderer:
        renderer.render(frame)
        deform = next(iter(renderer._renderer.scene.deforms.values()))
        return np.frombuffer(deform.mesh.vertices.read(), dtype=np.float32).reshape(-1, 8)


@pytest.mark.parametrize("frame", [1, 3, 4])
def test_gpu_morphed_vertices_equal_a_cpu_morphing(gl, tmp_path, frame):
    _skinned_glb(tmp_path / "arm.glb", skinned=False, morphed=True)
    vertices = _posed(gl, tmp_path, frame)
    positions, normals = cpu_morphing(frame / 4.0)
    assert np.abs(vertices[:, :3] - positions).max() < 1e-4
    assert np.abs(vertices[:, 3:6] - normals).max() < 1e-4
    # the part is then placed by its node (x = 2), not left at the origin
    part = scene(SCENE.replace("ANIMATION", "animation: {clip: bend, loop: false}"),
                 base_dir=tmp_path).world.objects[0]
    assert part.matrices(0.25)[0][0, 3] == pytest.approx(2.0)
    bounds = part.local_bounds(frame / 4.0)
    assert np.all(bounds[0] <= positions.min(axis=0) + 1e-9) and np.all(bounds[1] >= positions.max(axis=0) - 1e-9)


def test_a_skinned_and_morphed_part_is_morphed_then_skinned(gl, tmp_path):
    _skinned_glb(tmp_path / "arm.glb", skinned=True, morphed=True)
    vertices = _posed(gl, tmp_path, 2)
    morphed, _ = cpu_morphing(0.5)
    assert np.abs(vertices[:, :3] - cpu_skinning(0.5, morphed)).max() < 1e-4


def test_frames_of_a_skinned_clip_equal_frames_drawn_from_scratch(gl, tmp_path):
    """Posed vertices feed every pass, shadow maps too: a run's frames equal each frame
    rendered on its own (nothing drawn from them is kept from an earlier frame)."""
    from conftest import render

    _skinned_glb(tmp_path / "arm.glb", skinned=True, morphed=True)
    text = SCENE.replace("ANIMATION", "animation: {clip: bend, loop: false}").replace(
        "objects:", "lights: [{type: directional, direction: [-0.3, -1, -0.5], shadows: true}]\nobjects:\n"
                    "  - mesh: {primitive: plane, size: 6}")
    run = render(gl, text, frames=(0, 1, 3), base_dir=tmp_path)
    alone = [render(gl, text, frames=(i,), base_dir=tmp_path)[0] for i in (0, 1, 3)]
    assert all(np.array_equal(a, b) for a, b in zip(run, alone))
    assert not np.array_equal(run[0], run[2])

"""A glTF clip played on an object: each node that holds a mesh becomes a part of the object
that moves with its node (and so with every animated node above it).

A part's mesh is the node's geometry where the file places it at rest (world transform
W_rest); at time t the node's world transform is W(t), the file's hierarchy with the clip's
values at the clip's time, so the part is drawn with W(t) W_rest^-1 after the object's own
transform and instances: world = M_object M_instance W(t) W_rest^-1.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from scenerender.animation import Track
from scenerender.errors import display_path
from scenerender.mesh.gltf_animation import Clip, Skin, clip_time
from scenerender.mesh.loader import read_gltf_clips
from scenerender.scene.model.object_animation import GLTF_SUFFIXES
from scenerender.world.transforms import transformed_bounds, union_bounds
from scenerender.mesh.gltf_geometry import placed_nodes

# Marks a part as moving for everything that asks which inputs animate (animated_keys): its
# value is not used, only that it changes.
_MOVING = Track([0.0, 1.0], [0.0, 1.0], ["linear", "linear"])


@dataclass
class ClipPlayer:
    """One object's clip: the file's node hierarchy and the clip, played as ``animation``
    says (speed, offset, loop). Node transforms are worked out once per time asked."""

    header: dict
    clip: Clip
    speed: float
    offset: float
    loop: bool
    _cached: tuple = field(default=(None, None), repr=False)

    def node_worlds(self, t: float) -> dict:
        """node index -> its (4, 4) float64 world transform in the file at scene time ``t``."""
        if self._cached[0] != t:
            local = clip_time(t, self.clip.duration, self.speed, self.offset, self.loop)
            changed = self.clip.node_values(local)
            self._cached = (t, {index: world for index, _, world in placed_nodes(self.header, changed)})
        return self._cached[1]


@dataclass
class NodeMotion:
    """How one part moves: W(t) W_rest^-1 of its node (see the module docstring)."""

    player: ClipPlayer
    node: int
    rest_inverse: np.ndarray
    moving: Track = _MOVING

    def __call__(self, t: float) -> np.ndarray:
        return self.player.node_worlds(t)[self.node] @ self.rest_inverse


def find_clip(clips: list[Clip], wanted) -> Clip | None:
    """The clip ``wanted`` names: an index into the file's animations, or a name."""
    if isinstance(wanted, int):
        return clips[wanted] if wanted < len(clips) else None
    return next((clip for clip in clips if clip.name == wanted), None)


def clips_text(clips: list[Clip]) -> str:
    """'#0 'spin' (2 s), #1 (0.5 s)': each clip's index, name and duration."""
    return ", ".join(f"#{c.index}{' ' + repr(c.name) if c.name else ''} ({c.duration:g} s)" for c in clips)


def node_motions(header: dict, player: ClipPlayer, nodes: list[int]) -> dict:
    """node -> NodeMotion for each of ``nodes`` (the nodes holding meshes) that the clip
    moves (it drives the node or a node above it), None for the others, which stay where
    the file puts them, still (drawn and cached exactly as without the clip)."""
    rest = {index: world for index, _, world in placed_nodes(header)}
    driven = {channel.node for channel in player.clip.channels if channel.path in ("translation", "rotation", "scale")}
    parents = {child: index for index, node in enumerate(header.get("nodes", [])) for child in node.get("children", [])}
    # pinv: a node scaled to nothing at rest has no inverse (and no visible geometry)
    return {node: NodeMotion(player, node, np.linalg.pinv(rest[node])) if _moved(node, driven, parents) else None
            for node in nodes}


def _moved(node: int, driven: set, parents: dict) -> bool:
    """Whether ``node`` or a node above it is ``driven``."""
    seen = set()
    while node is not None and node not in seen:
        if node in driven:
            return True
        seen.add(node)
        node = parents.get(node)
    return False


def clip_lines(loaded) -> list[str]:
    """One line per glTF file the scene's objects use that holds animations: its clips
    with their durations (what ``scenerender validate`` lists)."""
    lines, seen = [], set()
    for obj in loaded.spec.objects:
        mesh = obj.mesh
        if not (isinstance(mesh, Path) and mesh.suffix.lower() in GLTF_SUFFIXES) or mesh in seen:
            continue
        seen.add(mesh)
        _, clips, _ = read_gltf_clips(mesh, loaded.assets)
        if clips:
            lines.append(f"  {display_path(mesh)}: clips {clips_text(clips)}")
    return lines


@dataclass
class SkinMotion:
    """A skinned node's part: its vertices (in the mesh's own space) placed by the joints,
    sum_k w_k P_jk v with P_j = W_j(t) IBM_j; the node's own transform is not used.

    joints (N, 4) float32 joint slots per vertex; weights (N, 4) float32, each row scaled
    to sum 1 (the specification asks for that; the bounds below rely on it)."""

    player: ClipPlayer
    skin: Skin
    joints: np.ndarray
    weights: np.ndarray
    moving: Track = _MOVING

    def palette(self, t: float) -> np.ndarray:
        """(J, 4, 4) float64: P_j = W_j(t) IBM_j for each joint slot j."""
        worlds = self.player.node_worlds(t)
        return np.stack([worlds[node] for node in self.skin.joints]) @ self.skin.inverse_binds

    def bounds(self, t: float, rest: np.ndarray) -> np.ndarray:
        """(2, 3) bounds of the skinned vertices at ``t``: each vertex is a weighted mean of
        its joints' placements of it, so it lies inside the union of the boxes the used
        joints make of the mesh's ``rest`` bounds."""
        palette = self.palette(t)
        used = np.unique(self.joints[self.weights > 0]).astype(int)
        return union_bounds([transformed_bounds(rest, palette[j][None]) for j in used])


def skin_motion(player: ClipPlayer, skins: list[Skin], skinning: dict) -> SkinMotion:
    """The SkinMotion of a part whose ``skinning`` (mesh.loader.load_gltf_nodes) names one
    of ``skins``."""
    skin = skins[skinning["skin"]]
    joints = skinning["joints"]
    if joints.size and (joints.min() < 0 or joints.max() >= len(skin.joints)):
        raise ValueError(f"a vertex names joint {int(joints.max())}, the skin has {len(skin.joints)}")
    weights = np.asarray(skinning["weights"], dtype=np.float64)
    totals = weights.sum(axis=1, keepdims=True)
    weights = np.where(totals > 0, weights / np.where(totals > 0, totals, 1.0), [[1.0, 0.0, 0.0, 0.0]])
    return SkinMotion(player, skin, joints.astype(np.float32), weights.astype(np.float32))

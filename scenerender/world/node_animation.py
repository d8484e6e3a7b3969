"""A glTF clip played on an object: each node that holds a mesh becomes a part of the object
that moves with its node (and so with every animated node above it).

A part's mesh is the node's geometry where the file places it at rest (world transform
W_rest); at time t the node's world transform is W(t), the file's hierarchy with the clip's
values at the clip's time, so the part is drawn with W(t) W_rest^-1 after the object's own
transform and instances: world = M_object M_instance W(t) W_rest^-1.

A part whose vertices move themselves (a skin, morph targets: ``Deformation``) keeps its
mesh in the mesh's own space instead; the GPU poses its vertices each frame
(rendering/scene_gpu.py GpuDeform), and a morphed part without a skin is then placed by
its node's whole world transform W(t).
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

    def chain_bounds(self, node: int) -> list[tuple]:
        """The nodes from the root down to ``node``, each node's transform over the whole
        clip as bounds on the sizes of its parts: ("matrix", (4, 4) float64: a node placed by
        its matrix, which no channel moves) or ("trs", translation (3,), scale (3,))."""
        nodes = self.header.get("nodes", [])
        parents = {child: index for index, entry in enumerate(nodes) for child in entry.get("children", [])}
        chain, seen = [], set()
        while node is not None and node not in seen:  # placed_nodes refuses a circle before this runs
            seen.add(node)
            chain.append(self._node_bound(node, nodes[node]))
            node = parents.get(node)
        return chain[::-1]

    def _node_bound(self, index: int, node: dict) -> tuple:
        if "matrix" in node:
            return "matrix", np.asarray(node["matrix"], dtype=np.float64).reshape(4, 4).T
        bounds = {"translation": np.abs(np.asarray(node.get("translation", (0.0, 0.0, 0.0)), dtype=np.float64)),
                  "scale": np.abs(np.asarray(node.get("scale", (1.0, 1.0, 1.0)), dtype=np.float64))}
        for channel in self.clip.channels:
            if channel.node == index and channel.path in bounds:
                bounds[channel.path] = np.maximum(bounds[channel.path], channel.magnitude_bound())
        return "trs", bounds["translation"], bounds["scale"]

    def weights_bound(self, node: int) -> np.ndarray | None:
        """(T,) bound on the sizes of the morph weights the clip gives ``node``, or None
        where no channel drives them."""
        channels = [c for c in self.clip.channels if c.node == node and c.path == "weights"]
        return channels[0].magnitude_bound() if channels else None

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


def node_motions(header: dict, player: ClipPlayer, nodes: list[int], unplaced: list[int] = ()) -> dict:
    """node -> NodeMotion for each of ``nodes`` (the nodes holding meshes placed at rest)
    that the clip moves (it drives the node or a node above it), None for the others,
    which stay where the file puts them, still (drawn and cached exactly as without the
    clip); and for each of ``unplaced`` (meshes in their own space: morphed parts), the
    node's whole world transform W(t)."""
    rest = {index: world for index, _, world in placed_nodes(header)}
    placing = {node: NodeMotion(player, node, np.eye(4)) for node in unplaced}
    driven = {channel.node for channel in player.clip.channels if channel.path in ("translation", "rotation", "scale")}
    parents = {child: index for index, node in enumerate(header.get("nodes", [])) for child in node.get("children", [])}
    # pinv: a node scaled to nothing at rest has no inverse (and no visible geometry)
    return {**{node: NodeMotion(player, node, np.linalg.pinv(rest[node])) if _moved(node, driven, parents) else None
               for node in nodes}, **placing}


def clip_moves(header: dict, clip: Clip, node: int) -> bool:
    """Whether ``clip`` drives ``node`` or a node above it."""
    driven = {channel.node for channel in clip.channels if channel.path in ("translation", "rotation", "scale")}
    parents = {child: index for index, node in enumerate(header.get("nodes", [])) for child in node.get("children", [])}
    return _moved(node, driven, parents)


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
class Deformation:
    """A part whose vertices move themselves, in the mesh's own space, before anything
    else places them: morph targets first (v + sum_i m_i dv_i, normals likewise), then the
    skin (sum_k w_k P_jk v with P_j = W_j(t) IBM_j). Either may be absent.

    skin: the file's Skin or None; joints (N, 4) float32 joint slots per vertex; weights
    (N, 4) float32, each row scaled to sum 1 (the specification asks for that; the bounds
    rely on it). targets: (T, N, 6) float32 position and normal deltas, or None; node:
    the node whose ``weights`` channel animates them; rest_weights (T,): its own weights."""

    player: ClipPlayer
    node: int
    skin: Skin | None = None
    joints: np.ndarray | None = None
    weights: np.ndarray | None = None
    targets: np.ndarray | None = None
    rest_weights: np.ndarray | None = None
    moving: Track = _MOVING

    def palette(self, t: float) -> np.ndarray | None:
        """(J, 4, 4) float64: P_j = W_j(t) IBM_j for each joint slot j; None without a skin."""
        if self.skin is None:
            return None
        worlds = self.player.node_worlds(t)
        return np.stack([worlds[node] for node in self.skin.joints]) @ self.skin.inverse_binds

    def morph_weights(self, t: float) -> np.ndarray | None:
        """(T,) float64: the targets' weights at ``t`` (the clip's ``weights`` channel of the
        node, else the node's or mesh's own); None without targets."""
        if self.targets is None:
            return None
        local = clip_time(t, self.player.clip.duration, self.player.speed, self.player.offset, self.player.loop)
        for channel in self.player.clip.channels:
            if channel.node == self.node and channel.path == "weights":
                return channel(local).reshape(-1)[:len(self.targets)]
        return self.rest_weights

    def bounds(self, t: float, rest: np.ndarray) -> np.ndarray:
        """(2, 3) bounds of the deformed vertices at ``t``: the rest bounds grown by each
        target's largest delta times its weight, then, with a skin, the union of the boxes
        the used joints make of that (each vertex is a weighted mean of its joints'
        placements of it)."""
        box = rest
        weights = self.morph_weights(t)
        if weights is not None:
            reach = np.abs(weights)[:, None] * np.abs(self.targets[:, :, :3]).max(axis=1)
            box = np.stack([rest[0] - reach.sum(axis=0), rest[1] + reach.sum(axis=0)])
        palette = self.palette(t)
        if palette is None:
            return box
        used = np.unique(self.joints[self.weights > 0]).astype(int)
        return union_bounds([transformed_bounds(box, palette[j][None]) for j in used])


def deformation(player: ClipPlayer, skins: list[Skin], node: int, deform: dict) -> Deformation:
    """The Deformation of a part from mesh.loader.load_gltf_nodes' ``deform``."""
    found = Deformation(player, node)
    if "skin" in deform:
        skin = skins[deform["skin"]]
        joints = deform["joints"]
        if joints.size and (joints.min() < 0 or joints.max() >= len(skin.joints)):
            raise ValueError(f"a vertex names joint {int(joints.max())}, the skin has {len(skin.joints)}")
        weights = np.asarray(deform["weights"], dtype=np.float64)
        totals = weights.sum(axis=1, keepdims=True)
        weights = np.where(totals > 0, weights / np.where(totals > 0, totals, 1.0), [[1.0, 0.0, 0.0, 0.0]])
        found.skin, found.joints, found.weights = skin, joints.astype(np.float32), weights.astype(np.float32)
    if "morph" in deform:
        morph = deform["morph"]
        found.targets = np.concatenate([morph["positions"], morph["normals"]], axis=2).astype(np.float32)
        found.rest_weights = morph["weights"]
    return found

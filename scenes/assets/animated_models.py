"""Writes models/fan_and_arm.glb: a desk fan and a two-bone arm whose glTF animation clips
show each interpolation (STEP, LINEAR, CUBICSPLINE) moving a node and its subtree, a skin
and a morph target.

Generated here from boxes (numpy only; the output is byte-identical each run), part of the
project under its licence (MIT)::

    python scenes/assets/animated_models.py

Clips (play one with ``animation: {clip: NAME}`` on an object whose mesh is the file):
  spin  2 s  LINEAR rotation: the fan's rotor turns once (keys every quarter turn, slerp)
  bend  2 s  CUBICSPLINE rotation of the elbow (the skinned tube bends, the hand
             follows), a LINEAR swing of the shoulder and the hand's grip (a morph
             target's weight, LINEAR)
  tick  2 s  STEP rotation: the fan's head snaps between three angles
  all   2 s  the three at once
"""
from __future__ import annotations

import json
import math
import struct
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parent / "models" / "fan_and_arm.glb"
FLOAT, UINT, USHORT = 5126, 5125, 5123


def box(size, center=(0.0, 0.0, 0.0)):
    """(positions (24, 3), normals (24, 3), faces (12, 3)) of an axis-aligned box, flat faces,
    counter-clockwise from outside."""
    half = np.asarray(size, dtype=np.float64) / 2.0
    positions, normals, faces = [], [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            normal = np.zeros(3)
            normal[axis] = sign
            u, v = [a for a in range(3) if a != axis]
            if sign < 0:
                u, v = v, u
            corners = []
            for du, dv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = np.zeros(3)
                p[axis] = sign * half[axis]
                p[u] = du * half[u]
                p[v] = dv * half[v]
                corners.append(p + center)
            start = len(positions)
            positions += corners
            normals += [normal] * 4
            faces += [[start, start + 1, start + 2], [start, start + 2, start + 3]]
    return np.array(positions), np.array(normals), np.array(faces)


def joined(*boxes):
    positions, normals, faces = [], [], []
    for p, n, f in boxes:
        faces.append(f + sum(len(x) for x in positions))
        positions.append(p)
        normals.append(n)
    return np.concatenate(positions), np.concatenate(normals), np.concatenate(faces)


def axis_angle(axis, degrees):
    """A unit quaternion (x, y, z, w)."""
    axis = np.asarray(axis, dtype=np.float64)
    half = math.radians(degrees) / 2.0
    return [*(axis / np.linalg.norm(axis) * math.sin(half)), math.cos(half)]


class Glb:
    """The few glTF pieces this file needs, written by hand."""

    def __init__(self):
        self.json = {"asset": {"version": "2.0", "generator": "scenerender scenes/assets/animated_models.py"},
                     "buffers": [{"byteLength": 0}], "bufferViews": [], "accessors": [], "meshes": [], "nodes": [],
                     "materials": [], "animations": [], "scenes": [{"nodes": []}], "scene": 0}
        self.binary = bytearray()

    def accessor(self, values, kind: str, component: int = FLOAT, target: int | None = None) -> int:
        data = np.ascontiguousarray(values, dtype={FLOAT: np.float32, UINT: np.uint32, USHORT: np.uint16}[component])
        while len(self.binary) % 4:
            self.binary += b"\0"
        view = {"buffer": 0, "byteOffset": len(self.binary), "byteLength": data.nbytes}
        if target is not None:
            view["target"] = target
        self.binary += data.tobytes()
        self.json["bufferViews"].append(view)
        accessor = {"bufferView": len(self.json["bufferViews"]) - 1, "componentType": component,
                    "count": int(len(data)), "type": kind}
        if kind in ("VEC3", "SCALAR") and component == FLOAT:
            accessor["min"] = np.atleast_1d(data.min(axis=0)).tolist()
            accessor["max"] = np.atleast_1d(data.max(axis=0)).tolist()
        self.json["accessors"].append(accessor)
        return len(self.json["accessors"]) - 1

    def material(self, name: str, color, metallic: float = 0.0, roughness: float = 0.6) -> int:
        self.json["materials"].append({"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": [*color, 1.0], "metallicFactor": metallic, "roughnessFactor": roughness}})
        return len(self.json["materials"]) - 1

    def mesh(self, name: str, geometry, material: int, skin=None, targets=()) -> int:
        """skin: (joints (N, 4), weights (N, 4)); targets: position deltas (N, 3) each."""
        positions, normals, faces = geometry
        attributes = {"POSITION": self.accessor(positions, "VEC3", target=34962),
                      "NORMAL": self.accessor(normals, "VEC3", target=34962)}
        if skin is not None:
            attributes["JOINTS_0"] = self.accessor(skin[0], "VEC4", USHORT, target=34962)
            attributes["WEIGHTS_0"] = self.accessor(skin[1], "VEC4", target=34962)
        primitive = {"attributes": attributes, "material": material,
                     "indices": self.accessor(faces.reshape(-1), "SCALAR", UINT, target=34963)}
        if len(targets):
            primitive["targets"] = [{"POSITION": self.accessor(delta, "VEC3", target=34962)} for delta in targets]
        self.json["meshes"].append({"name": name, "primitives": [primitive]})
        return len(self.json["meshes"]) - 1

    def skin(self, joints: list, inverse_binds: np.ndarray) -> int:
        """A skin over the ``joints`` nodes, their (J, 4, 4) inverse bind matrices (rows first)."""
        binds = self.accessor(np.asarray(inverse_binds).transpose(0, 2, 1).reshape(-1, 16), "MAT4")
        self.json.setdefault("skins", []).append({"joints": list(joints), "inverseBindMatrices": binds})
        return len(self.json["skins"]) - 1

    def node(self, name: str, mesh: int | None = None, children=(), root: bool = False, **fields) -> int:
        node = {"name": name, **fields}
        if mesh is not None:
            node["mesh"] = mesh
        if children:
            node["children"] = list(children)
        self.json["nodes"].append(node)
        if root:
            self.json["scenes"][0]["nodes"].append(len(self.json["nodes"]) - 1)
        return len(self.json["nodes"]) - 1

    def clip(self, name: str, channels) -> None:
        """channels: (node, path, times, values, interpolation)."""
        clip = {"name": name, "channels": [], "samplers": []}
        for node, path, times, values, interpolation in channels:
            values = np.asarray(values, dtype=np.float64)
            clip["samplers"].append({"input": self.accessor(times, "SCALAR"),
                                     "output": self.accessor(values, "SCALAR" if values.shape[1] == 1
                                                             else f"VEC{values.shape[1]}"),
                                     "interpolation": interpolation})
            clip["channels"].append({"sampler": len(clip["samplers"]) - 1, "target": {"node": node, "path": path}})
        self.json["animations"].append(clip)

    def bytes(self) -> bytes:
        while len(self.binary) % 4:
            self.binary += b"\0"
        self.json["buffers"][0]["byteLength"] = len(self.binary)
        text = json.dumps(self.json, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        body = (struct.pack("<II", len(text), 0x4E4F534A) + text
                + struct.pack("<II", len(self.binary), 0x004E4942) + bytes(self.binary))
        return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body


def fan(glb: Glb) -> tuple[int, int, int]:
    """(fan root, head, rotor): a 1.1 m desk fan at x = -0.9 facing +Z, its rotor turning
    about its axis."""
    metal = glb.material("fan_metal", (0.55, 0.57, 0.6), metallic=1.0, roughness=0.35)
    blade_colour = glb.material("fan_blade", (0.15, 0.35, 0.75))
    base = glb.mesh("fan_base", joined(box((0.5, 0.06, 0.4), (0, 0.03, 0)), box((0.06, 0.8, 0.06), (0, 0.46, 0))),
                    metal)
    head = glb.mesh("fan_head", box((0.18, 0.18, 0.25)), metal)
    blades = [box((0.12, 0.4, 0.02), (0.0, 0.22, 0.0))]
    for k in range(1, 4):  # four blades round the hub
        p, n, f = blades[0]
        c, s = math.cos(k * math.pi / 2), math.sin(k * math.pi / 2)
        turn = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        blades.append((p @ turn.T, n @ turn.T, f))
    rotor_mesh = glb.mesh("fan_rotor", joined(box((0.1, 0.1, 0.06)), *blades), blade_colour)
    rotor = glb.node("rotor", rotor_mesh, translation=[0.0, 0.0, 0.16])
    head_node = glb.node("head", head, children=[rotor], translation=[0.0, 0.9, 0.0])
    root = glb.node("fan", base, children=[head_node], root=True, translation=[-0.9, 0.0, 0.0])
    return root, head_node, rotor


def tube(length: float, width: float, rings: int):
    """A square tube along +X from 0 to ``length``, ``rings`` rings of 4 vertices, capped:
    (positions, normals, faces), smooth sides."""
    half = width / 2.0
    corners = np.array([[half, half], [-half, half], [-half, -half], [half, -half]])  # (y, z), turning about +X
    positions, normals, faces = [], [], []
    for k in range(rings):
        x = length * k / (rings - 1)
        for y, z in corners:
            positions.append([x, y, z])
            normals.append([0.0, y / half / math.sqrt(2.0), z / half / math.sqrt(2.0)])
    for k in range(rings - 1):
        for side in range(4):
            a, b = 4 * k + side, 4 * k + (side + 1) % 4
            faces += [[a, b, a + 4], [b, b + 4, a + 4]]
    last = 4 * (rings - 1)
    faces += [[0, 2, 1], [0, 3, 2], [last, last + 1, last + 2], [last, last + 2, last + 3]]
    return np.array(positions), np.array(normals), np.array(faces)


def arm(glb: Glb) -> tuple[int, int, int]:
    """(shoulder, elbow, hand): a two-bone arm on a post at x = 0.6, 0.5 m bones along +X:
    one skinned tube over the shoulder and elbow joints (the elbow bends it smoothly), a
    hand whose morph target closes its grip."""
    skin_colour = glb.material("arm", (0.85, 0.55, 0.35), roughness=0.8)
    joint = glb.material("joint", (0.2, 0.2, 0.22), metallic=1.0, roughness=0.4)
    post = glb.mesh("post", box((0.12, 1.0, 0.12), (0, 0.5, 0)), joint)
    positions, normals, faces = tube(1.0, 0.1, 21)
    bend = np.clip((positions[:, 0] - 0.42) / 0.16, 0.0, 1.0)  # shoulder to elbow over 16 cm about the elbow
    joints = np.tile([0, 1, 0, 0], (len(positions), 1))
    weights = np.stack([1.0 - bend, bend, 0 * bend, 0 * bend], axis=1)
    shoulder_at = np.array([0.6, 1.05, 0.0])  # where the tube sits at rest, in the file's space
    geometry = (positions + shoulder_at, normals, faces)
    tube_mesh = glb.mesh("arm_tube", geometry, skin_colour, skin=(joints, weights))
    hand_geometry = box((0.16, 0.06, 0.14), (0.08, 0, 0))
    grip = np.where(hand_geometry[0][:, [0]] > 0.1, [0.0, -0.04, 0.0], 0.0) * np.sign(hand_geometry[0][:, [1]])
    hand = glb.mesh("hand", hand_geometry, joint, targets=[grip])
    hand_node = glb.node("hand", hand, translation=[0.5, 0.0, 0.0])
    elbow = glb.node("elbow", children=[hand_node], translation=[0.5, 0.0, 0.0])
    shoulder = glb.node("shoulder", children=[elbow], translation=[0.0, 1.05, 0.0])
    glb.node("arm", post, children=[shoulder], root=True, translation=[0.6, 0.0, 0.0])
    rest = [np.eye(4), np.eye(4)]
    for matrix, offset in zip(rest, (shoulder_at, shoulder_at + [0.5, 0.0, 0.0])):
        matrix[:3, 3] = -offset  # the inverse of each joint's world transform at rest (translations only)
    skin = glb.skin([shoulder, elbow], np.stack(rest))
    glb.node("arm_skin", tube_mesh, root=True, skin=skin)
    return shoulder, elbow, hand_node


def build() -> bytes:
    glb = Glb()
    _, head, rotor = fan(glb)
    shoulder, elbow, hand = arm(glb)
    quarter_turns = [axis_angle((0, 0, 1), -90 * k) for k in range(5)]
    glb.clip("spin", [(rotor, "rotation", np.linspace(0.0, 2.0, 5), quarter_turns, "LINEAR")])
    # the elbow bends up to 100 degrees and back, eased by the spline's tangents
    bent = [axis_angle((0, 0, 1), a) for a in (0.0, 100.0, 0.0)]
    zero = [0.0, 0.0, 0.0, 0.0]
    cubic = [zero, bent[0], zero, zero, bent[1], zero, zero, bent[2], zero]  # in-tangent, value, out-tangent
    swing = [axis_angle((0, 1, 0), a) for a in (-30.0, 30.0, -30.0)]
    grip = [[0.0], [1.0], [0.0]]  # the hand closes as the elbow bends
    glb.clip("bend", [(elbow, "rotation", [0.0, 1.0, 2.0], cubic, "CUBICSPLINE"),
                      (shoulder, "rotation", [0.0, 1.0, 2.0], swing, "LINEAR"),
                      (hand, "weights", [0.0, 1.0, 2.0], grip, "LINEAR")])
    snaps = [axis_angle((0, 1, 0), a) for a in (-35.0, 0.0, 35.0, 35.0)]
    tick = (head, "rotation", [0.0, 0.67, 1.33, 2.0], snaps, "STEP")
    glb.clip("tick", [tick])
    glb.clip("all", [(rotor, "rotation", np.linspace(0.0, 2.0, 5), quarter_turns, "LINEAR"),
                     (elbow, "rotation", [0.0, 1.0, 2.0], cubic, "CUBICSPLINE"),
                     (shoulder, "rotation", [0.0, 1.0, 2.0], swing, "LINEAR"),
                     (hand, "weights", [0.0, 1.0, 2.0], grip, "LINEAR"), tick])
    return glb.bytes()


if __name__ == "__main__":
    OUT.write_bytes(build())
    print(f"{OUT.relative_to(Path.cwd()) if OUT.is_relative_to(Path.cwd()) else OUT}: {OUT.stat().st_size} bytes")

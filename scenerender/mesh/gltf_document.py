"""The shape of a glTF file's JSON, as far as scenerender reads it: the typed model every
glTF file is validated into before any reader walks it (mesh.gltf.split_glb).

It checks structure, not meaning: each collection is a list of objects, each nested part
an object, each reference a whole number, each node transform a list of finite numbers,
each name text. What a value means (an index in range, a factor in [0, 1], an
interpolation glTF knows) the readers still judge, each with its own message: a material's
unusable value is a warning, a malformed animation an error. Keys scenerender does not
read (``extras``, extensions it ignores, cameras...) are not looked at.
"""
from __future__ import annotations

import math
from typing import Annotated, Any

from pydantic import BaseModel, ConfigDict, Field, FiniteFloat, field_validator


def _numbers(count: int):
    return Annotated[list[FiniteFloat], Field(min_length=count, max_length=count)]


class _Part(BaseModel):
    # strict: 1.0 is no index, "1" no number; keys not listed here are the file's business
    model_config = ConfigDict(strict=True, extra="allow")


class TextureInfo(_Part):
    index: int | None = None
    texCoord: int | None = None
    extensions: dict[str, Any] = {}


class PbrMetallicRoughness(_Part):
    baseColorTexture: TextureInfo | None = None
    metallicRoughnessTexture: TextureInfo | None = None


class Material(_Part):
    name: str | None = None
    pbrMetallicRoughness: PbrMetallicRoughness | None = None
    normalTexture: TextureInfo | None = None
    occlusionTexture: TextureInfo | None = None
    emissiveTexture: TextureInfo | None = None
    extensions: dict[str, Any] = {}


class Texture(_Part):
    source: int | None = None
    sampler: int | None = None


class Image(_Part):
    uri: str | None = None
    bufferView: int | None = None


class Sampler(_Part):
    magFilter: int | None = None
    wrapS: int | None = None


class Buffer(_Part):
    uri: str | None = None


class BufferView(_Part):
    buffer: int | None = None
    byteOffset: int = 0
    byteLength: int | None = None
    byteStride: int | None = None


class Accessor(_Part):
    bufferView: int | None = None
    byteOffset: int = 0
    componentType: int | None = None
    normalized: bool = False
    count: int | None = None
    type: str | None = None
    sparse: dict[str, Any] | None = None


class Primitive(_Part):
    attributes: dict[str, int] = {}
    indices: int | None = None
    material: int | None = None
    mode: int = 4
    targets: list[dict[str, int]] = []
    extensions: dict[str, Any] = {}


class Mesh(_Part):
    primitives: list[Primitive] = []
    weights: list[FiniteFloat] | None = None


class Node(_Part):
    name: str | None = None
    children: list[int] = []
    mesh: int | None = None
    skin: int | None = None
    matrix: _numbers(16) | None = None
    translation: _numbers(3) | None = None
    rotation: _numbers(4) | None = None
    scale: _numbers(3) | None = None
    weights: list[FiniteFloat] | None = None

    @field_validator("rotation")
    @classmethod
    def _a_rotation(cls, rotation):
        if rotation is not None and not math.hypot(*rotation) > 0.0:
            raise ValueError("a rotation needs a quaternion of non-zero length")
        return rotation


class Scene(_Part):
    nodes: list[int] = []


class ChannelTarget(_Part):
    node: int | None = None
    path: str | None = None


class Channel(_Part):
    sampler: int | None = None
    target: ChannelTarget = ChannelTarget()


class AnimationSampler(_Part):
    input: int | None = None
    output: int | None = None
    interpolation: str = "LINEAR"


class Animation(_Part):
    name: str | None = None
    channels: list[Channel] = []
    samplers: list[AnimationSampler] = []


class Skin(_Part):
    joints: list[int] = []
    inverseBindMatrices: int | None = None


class GltfDocument(_Part):
    """A glTF file's JSON: what the readers (mesh.gltf, gltf_geometry, gltf_animation) use."""

    scene: int | None = None
    scenes: list[Scene] = []
    nodes: list[Node] = []
    meshes: list[Mesh] = []
    materials: list[Material] = []
    textures: list[Texture] = []
    images: list[Image] = []
    samplers: list[Sampler] = []
    buffers: list[Buffer] = []
    bufferViews: list[BufferView] = []
    accessors: list[Accessor] = []
    animations: list[Animation] = []
    skins: list[Skin] = []
    extensionsUsed: list[str] = []
    extensionsRequired: list[str] = []

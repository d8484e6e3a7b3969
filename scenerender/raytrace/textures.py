"""Texture lookups for the reference: the base level of a map, bilinear (or nearest), with
the material's wrap mode and the map's uv scale and offset, as the forward shader's
``map_uv`` and the GL sampler do. Colour maps are decoded from sRGB before filtering, like
the GPU's sRGB textures. Averaging many such lookups per pixel is the box-filtered truth
that mipmapping approximates."""
from __future__ import annotations

import numpy as np

from scenerender.colorspace import srgb_decode
from scenerender.world.images import placeholder_pixels


class MapSampler:
    """One material map ready to sample.

    pixels: (H, W, 4) uint8 RGBA, top row first (as decoded); srgb: decode colour first.
    wrap: "repeat" | "clamp" | "mirror"; nearest: True for ``filter: nearest`` and the
    placeholder (the GPU samples those with GL_NEAREST). uv_set: the mesh's texture
    coordinates it reads (0, or 1: glTF texCoord: 1)."""

    def __init__(self, pixels: np.ndarray, srgb: bool, wrap: str, nearest: bool, uv_scale, uv_offset,
                 uv_skew=(0.0, 0.0), uv_set: int = 0):
        self.uv_set = uv_set
        values = pixels.astype(np.float64) / 255.0
        if srgb:
            values[:, :, :3] = srgb_decode(values[:, :, :3])
        self.texels = values[::-1]  # row 0 at v = 0, the image's bottom edge, as GL stores it
        self.wrap = wrap
        self.nearest = nearest
        self.scale = np.asarray(uv_scale, dtype=np.float64)
        self.offset = np.asarray(uv_offset, dtype=np.float64)
        self.skew = np.asarray(uv_skew, dtype=np.float64)

    @classmethod
    def for_source(cls, source, material, images) -> "MapSampler":
        """The sampler of a TextureSource of ``material``; ``images`` the World's ImageStore."""
        if source.is_placeholder:
            return cls(placeholder_pixels(), False, material.wrap, True, source.uv_scale, source.uv_offset,
                       source.uv_skew, source.uv_set)
        return cls(images.pixels(source.path), source.srgb, material.wrap, material.filter == "nearest",
                   source.uv_scale, source.uv_offset, source.uv_skew, source.uv_set)

    def sample(self, uv: np.ndarray) -> np.ndarray:
        """(P, 2) float64 texture coordinates -> (P, 4) float64 RGBA, linear."""
        t = uv * self.scale + uv[:, ::-1] * self.skew + self.offset
        if self.wrap == "mirror":
            t = 1.0 - np.abs(1.0 - np.mod(t, 2.0))
        height, width = self.texels.shape[:2]
        x, y = t[:, 0] * width, t[:, 1] * height
        if self.nearest:
            return self.texels[self._wrap(np.floor(y), height), self._wrap(np.floor(x), width)]
        x, y = x - 0.5, y - 0.5
        x0, y0 = np.floor(x), np.floor(y)
        fx, fy = (x - x0)[:, None], (y - y0)[:, None]
        c0, c1 = self._wrap(x0, width), self._wrap(x0 + 1, width)
        r0, r1 = self._wrap(y0, height), self._wrap(y0 + 1, height)
        top = self.texels[r0, c0] * (1 - fx) + self.texels[r0, c1] * fx
        bottom = self.texels[r1, c0] * (1 - fx) + self.texels[r1, c1] * fx
        return top * (1 - fy) + bottom * fy

    def _wrap(self, index: np.ndarray, size: int) -> np.ndarray:
        """Texel indices wrapped as the sampler wraps them (mirror is folded already)."""
        if self.wrap == "clamp":
            return np.clip(index, 0, size - 1).astype(np.int64)
        return np.mod(index, size).astype(np.int64)

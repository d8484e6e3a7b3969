"""Allocate the render graph's resources (textures, renderbuffers) and framebuffers."""
from __future__ import annotations

import moderngl

_COLOR_FORMATS = {  # format -> (components, dtype)
    "rgba8": (4, "f1"),
    "rgba16f": (4, "f2"),
    "rg16f": (2, "f2"),
    "r8": (1, "f1"),
    "r16f": (1, "f2"),
}


def allocate(ctx, desc):
    """A moderngl texture or renderbuffer for a ``graph.ResourceDesc``."""
    size = tuple(int(v) for v in desc.size)
    multisampled = desc.samples > 1
    if desc.kind == "depth":
        if multisampled:
            return ctx.depth_renderbuffer(size, samples=desc.samples)
        texture = ctx.depth_texture(size)
        texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        texture.repeat_x = texture.repeat_y = False
        return texture
    components, dtype = _COLOR_FORMATS[desc.format]
    if multisampled:
        return ctx.renderbuffer(size, components, samples=desc.samples, dtype=dtype)
    texture = ctx.texture(size, components, dtype=dtype)
    texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
    texture.repeat_x = texture.repeat_y = False
    return texture


class FramebufferCache:
    """One framebuffer per combination of attachments, made on first use."""

    def __init__(self, ctx):
        self.ctx = ctx
        self._fbos: dict = {}

    def get(self, colors: tuple, depth=None):
        key = tuple(id(c) for c in colors) + (id(depth) if depth is not None else None,)
        fbo = self._fbos.get(key)
        if fbo is None:
            fbo = self.ctx.framebuffer(color_attachments=list(colors), depth_attachment=depth)
            self._fbos[key] = fbo
        return fbo

    def release(self) -> None:
        for fbo in self._fbos.values():
            fbo.release()
        self._fbos.clear()

"""Allocate the render graph's resources (textures, renderbuffers) and framebuffers."""
from __future__ import annotations

import moderngl

GL_SRGB8_ALPHA8 = 0x8C43
GL_FRAMEBUFFER_SRGB = 0x8DB9

_COLOR_FORMATS = {  # format -> (components, dtype, internal format or None for the default)
    "rgba8": (4, "f1", None),
    # linear colour stored sRGB-encoded in 8 bits: with GL_FRAMEBUFFER_SRGB on, writes
    # encode and blending decodes in the driver, and sampling returns linear values
    "srgba8": (4, "f1", GL_SRGB8_ALPHA8),
    "rgba16f": (4, "f2", None),
    "rgba32f": (4, "f4", None),  # the data views' values kept whole for EXR output
    "r8": (1, "f1", None),
    "r16ui": (1, "u2", None),  # object ids (unsigned integers, never filtered)
    "r32f": (1, "f4", None),
    # values packed by the shaders (packHalf2x16, floatBitsToUint): the environment
    # visibility's, read in fewer fetches (never filtered)
    "r32ui": (1, "u4", None),
    "rgba32ui": (4, "u4", None),
}


def allocate(ctx, desc, depth_convention=None):
    """A moderngl texture or renderbuffer for a ``graph.ResourceDesc``.

    Makes every format the graph offers (graph.COLOR_FORMATS, graph.DEPTH_FORMATS).
    "camera_depth" is the depth format ``depth_convention`` (gpu.depth.DepthConvention)
    picks for the device: 24-bit, or 32-bit float renderbuffers whose storage the
    convention sets up (only ever attached, never sampled)."""
    size = tuple(int(v) for v in desc.size)
    multisampled = desc.samples > 1
    depth_format = desc.format
    if depth_format == "camera_depth":
        depth_format = depth_convention.depth_format if depth_convention is not None else "depth24"
    if desc.kind == "depth" and depth_format == "depth32f":
        buffer = ctx.depth_renderbuffer(size, samples=desc.samples if multisampled else 0)
        depth_convention.make_float_depth(buffer, size, desc.samples if multisampled else 0)
        return buffer
    if desc.kind == "depth":
        if multisampled:
            return ctx.depth_renderbuffer(size, samples=desc.samples)
        texture = ctx.depth_texture(size)
        texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        texture.repeat_x = texture.repeat_y = False
        return texture
    components, dtype, internal_format = _COLOR_FORMATS[desc.format]
    # multisampled colour is a texture too, so a pass can read its samples (sampler2DMS)
    texture = ctx.texture(size, components, dtype=dtype, samples=desc.samples if multisampled else 0,
                          internal_format=internal_format)
    if multisampled:
        return texture
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

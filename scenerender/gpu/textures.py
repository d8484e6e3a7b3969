"""Images to GL textures, uploaded once per colour space.

Decoding is CPU work in ``scenerender.world.images`` (checked, GL-free); the world decodes
every image while it is built, and this cache uploads those pixels.

Colour maps are uploaded as sRGB textures so the GPU linearises them *before* filtering,
which is what makes bilinear filtering of colour correct. Mipmap levels are made on the
CPU (``world.mipmaps``, averaged in linear light) and uploaded with the image.
"""
from __future__ import annotations

import ctypes
from functools import lru_cache
from pathlib import Path

import moderngl
import numpy as np

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.world.images import PLACEHOLDER_SIZE, ImageStore, placeholder_pixels
from scenerender.world.mipmaps import mip_chain

GL_SRGB8_ALPHA8 = 0x8C43
_GL_RGBA8, _GL_RGBA, _GL_UNSIGNED_BYTE = 0x8058, 0x1908, 0x1401
_GL_TEXTURE_2D, _GL_TEXTURE_CUBE_MAP_POSITIVE_X = 0x0DE1, 0x8515

__all__ = ["GL_SRGB8_ALPHA8", "PLACEHOLDER_SIZE", "TextureCache", "placeholder_pixels"]


class TextureCache:
    """GL textures by (file, colour space); the placeholder for files that are missing.

    ``images`` holds the decoded pixels (the world's store); files not in it are decoded on
    first use.
    """

    def __init__(self, ctx, images: ImageStore | None = None):
        self.ctx = ctx
        self._images = images if images is not None else ImageStore()
        self._textures: dict = {}
        self._owned: list[int] = []  # GL names of textures made here, not by moderngl

    def texture_2d(self, path: Path | None, srgb: bool):
        key = (str(path) if path else None, srgb)
        texture = self._textures.get(key)
        if texture is None:
            texture = self._placeholder() if path is None else self._loaded_2d(path, srgb)
            self._textures[key] = texture
        return texture

    def cube_map(self, faces: list[Path]):
        """A cube map from six images in +X -X +Y -Y +Z -Z order (sRGB)."""
        key = ("cube",) + tuple(str(p) for p in faces)
        texture = self._textures.get(key)
        if texture is None:
            texture = self._upload_cube(faces)
            self._textures[key] = texture
        return texture

    @property
    def count(self) -> int:
        return len(self._textures)

    def release(self) -> None:
        for texture in self._textures.values():
            texture.release()
        self._textures.clear()
        if self._owned:
            names = (ctypes.c_uint * len(self._owned))(*self._owned)
            _gl_storage_calls().delete_textures(len(self._owned), names)
            self._owned.clear()

    def _pixels(self, path: Path) -> np.ndarray:
        return self._images.pixels(path)

    def _loaded_2d(self, path: Path, srgb: bool):
        """The texture of ``path``; running out of memory on the way is a UserError naming it."""
        try:
            return self._upload_2d(self._pixels(path), srgb)
        except MemoryError:
            raise UserError(f"not enough memory to load this texture ({_size_text(path, self._images)}); "
                            "use a smaller image, or lower --limit texture_pixels=N to refuse such images early",
                            SourceLocation(display_path(path))) from None

    def _upload_2d(self, pixels: np.ndarray, srgb: bool):
        """A texture of ``pixels`` (H, W, 4) uint8, top row first, and its mip levels. GL's
        first row is the bottom one (and OBJ's v = 0 is the image's bottom edge), so rows
        go up flipped, a band at a time: no flipped copy of a whole large image is made.
        Storage for every level is made at once (glTexStorage2D) where the GL has it: levels
        added one by one make Mesa copy the whole texture into a new allocation when it is
        first drawn, which held a 12,000 x 12,000 texture twice."""
        height, width = pixels.shape[:2]
        gl = _gl_storage_calls()
        if gl is None:
            texture = self.ctx.texture((width, height), 4, None, internal_format=GL_SRGB8_ALPHA8 if srgb else None)
        else:
            texture = self._storage_texture(gl, width, height, srgb)
        for top in range(0, height, _UPLOAD_ROWS):
            bottom = min(height, top + _UPLOAD_ROWS)
            band = np.ascontiguousarray(pixels[top:bottom][::-1])
            texture.write(band, viewport=(0, height - bottom, width, bottom - top))
        _add_mip_levels(texture, [(_GL_TEXTURE_2D, pixels)], srgb, flip=True, allocated=gl is not None)
        return texture

    def _storage_texture(self, gl: "_StorageCalls", width: int, height: int, srgb: bool):
        name = ctypes.c_uint(0)
        gl.gen_textures(1, ctypes.byref(name))
        texture = self.ctx.external_texture(name.value, (width, height), 4, 0, "f1")
        texture.use(self.ctx.default_texture_unit)  # bound where moderngl makes its own uploads
        levels = max(width, height).bit_length()
        gl.tex_storage_2d(_GL_TEXTURE_2D, levels, GL_SRGB8_ALPHA8 if srgb else _GL_RGBA8, width, height)
        self._owned.append(name.value)
        return texture

    def _placeholder(self):
        pixels = placeholder_pixels()
        texture = self.ctx.texture((PLACEHOLDER_SIZE, PLACEHOLDER_SIZE), 4, pixels.tobytes())
        texture.filter = (moderngl.NEAREST, moderngl.NEAREST)
        return texture

    def _upload_cube(self, faces: list[Path]):
        images = [self._pixels(p) for p in faces]
        size = images[0].shape[:2]
        for path, image in zip(faces, images):
            if image.shape[:2] != size or size[0] != size[1]:
                raise UserError(f"skybox faces must be square and all the same size; this one is "
                                f"{image.shape[1]}x{image.shape[0]}, the first {size[1]}x{size[0]}",
                                SourceLocation(display_path(path)))
        # Cube-map faces keep the image's own row order (top row first): that is the
        # orientation the cube-map lookup convention expects.
        data = b"".join(np.ascontiguousarray(image).tobytes() for image in images)
        texture = self.ctx.texture_cube((size[1], size[0]), 4, data, internal_format=GL_SRGB8_ALPHA8)
        faces_by_target = [(_GL_TEXTURE_CUBE_MAP_POSITIVE_X + i, image) for i, image in enumerate(images)]
        _add_mip_levels(texture, faces_by_target, srgb=True)
        return texture


_UPLOAD_ROWS = 1024  # rows of a texture sent to GL at a time


def _add_mip_levels(texture, images: list, srgb: bool, flip: bool = False, allocated: bool = False) -> None:
    """Give ``texture`` every mipmap level below its images [(GL target, (H, W, 4) uint8)]
    and trilinear filtering; ``flip``: each level goes up bottom row first (the levels of a
    flipped image are the flipped levels: every filter window is symmetric); ``allocated``:
    the texture has storage for every level already (filled with glTexSubImage2D).

    No anisotropic filtering: Mesa llvmpipe's anisotropic sampler can stall for seconds
    (and has hung outright here) on some pixels, and leaving it off keeps software and GPU
    renders filtering textures the same way."""
    tex_image = _gl_tex_image_2d()
    if tex_image is None:  # no way to upload levels on this GL: the driver makes them
        texture.build_mipmaps()
        return
    # bound on the unit moderngl keeps for its own uploads, so no material's binding moves;
    # rows of RGBA8 need no unpack alignment beyond the 1 moderngl leaves set
    texture.use(texture.ctx.default_texture_unit)
    internal = GL_SRGB8_ALPHA8 if srgb else _GL_RGBA8
    sub_image = _gl_storage_calls().tex_sub_image_2d if allocated else None
    for target, image in images:
        for level, pixels in enumerate(mip_chain(image, srgb), start=1):
            pixels = np.ascontiguousarray(pixels[::-1]) if flip else pixels
            if sub_image is not None:
                sub_image(target, level, 0, 0, pixels.shape[1], pixels.shape[0], _GL_RGBA, _GL_UNSIGNED_BYTE,
                          pixels.ctypes.data)
            else:
                tex_image(target, level, internal, pixels.shape[1], pixels.shape[0], 0, _GL_RGBA, _GL_UNSIGNED_BYTE,
                          pixels.ctypes.data)
    texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)


@lru_cache(maxsize=1)
def _gl_tex_image_2d():
    """glTexImage2D of the current GL context (moderngl uploads level 0 only), or None."""
    address = _gl_function(b"glTexImage2D")
    if address is None:
        return None
    return ctypes.CFUNCTYPE(None, ctypes.c_uint, ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_int,
                            ctypes.c_int, ctypes.c_uint, ctypes.c_uint, ctypes.c_void_p)(address)


class _StorageCalls:
    """glGenTextures, glTexStorage2D, glTexSubImage2D and glDeleteTextures (GL 4.2)."""

    def __init__(self, addresses: dict):
        uint, sizei, pointer = ctypes.c_uint, ctypes.c_int, ctypes.c_void_p
        self.gen_textures = ctypes.CFUNCTYPE(None, sizei, ctypes.POINTER(uint))(addresses[b"glGenTextures"])
        self.delete_textures = ctypes.CFUNCTYPE(None, sizei, ctypes.POINTER(uint))(addresses[b"glDeleteTextures"])
        self.tex_storage_2d = ctypes.CFUNCTYPE(None, uint, sizei, uint, sizei, sizei)(addresses[b"glTexStorage2D"])
        self.tex_sub_image_2d = ctypes.CFUNCTYPE(None, uint, ctypes.c_int, ctypes.c_int, ctypes.c_int, sizei, sizei,
                                                 uint, uint, pointer)(addresses[b"glTexSubImage2D"])


@lru_cache(maxsize=1)
def _gl_storage_calls() -> _StorageCalls | None:
    names = (b"glGenTextures", b"glDeleteTextures", b"glTexStorage2D", b"glTexSubImage2D")
    addresses = {name: _gl_function(name) for name in names}
    return None if None in addresses.values() else _StorageCalls(addresses)


def _gl_function(name: bytes) -> int | None:
    """The address of GL function ``name`` through EGL (which resolves core functions for
    the current context, also on GPU drivers), or None."""
    try:
        egl = ctypes.CDLL("libEGL.so.1")
    except OSError:
        return None
    egl.eglGetProcAddress.restype = ctypes.c_void_p
    egl.eglGetProcAddress.argtypes = [ctypes.c_char_p]
    return egl.eglGetProcAddress(name) or None


def _size_text(path: Path, images: ImageStore) -> str:
    try:
        height, width = images.size(path)
    except Exception:  # noqa: BLE001 - only for the message
        return "its size unknown"
    return f"{width}x{height}, {width * height * 4 / 2**20:,.0f} MiB as RGBA"


# half floats end at 65504; a brighter texel (a sun in an HDR image) is kept at that
HALF_FLOAT_MAX = 65504.0


def environment_texture(ctx, linear: np.ndarray, mipmaps: bool = False):
    """An RGBA16F texture of an equirectangular image (H, W, 3) of linear radiance, its
    first row (+Y) at t = 0, filtered linearly, wrapping around in u; with ``mipmaps``,
    every level below it too (the GPU's box filter: the prefilter pass reads coarse levels
    for wide samples)."""
    height, width = linear.shape[:2]
    rgba = np.ones((height, width, 4), dtype=np.float16)
    rgba[..., :3] = np.clip(linear, 0.0, HALF_FLOAT_MAX)
    texture = ctx.texture((width, height), 4, rgba.tobytes(), dtype="f2")
    texture.repeat_x, texture.repeat_y = True, False
    if mipmaps:
        texture.build_mipmaps()
        texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    else:
        texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
    return texture

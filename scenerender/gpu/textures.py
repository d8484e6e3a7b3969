"""Images to GL textures, uploaded once per colour space.

Decoding is CPU work in ``scenerender.world.images`` (checked, GL-free); the world decodes
every image while it is built, and this cache uploads those pixels.

Colour maps are uploaded as sRGB textures so the GPU linearises them *before* filtering,
which is what makes mipmaps and bilinear filtering of colour correct.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.world.images import PLACEHOLDER_SIZE, ImageStore, placeholder_pixels

GL_SRGB8_ALPHA8 = 0x8C43

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

    def texture_2d(self, path: Path | None, srgb: bool):
        key = (str(path) if path else None, srgb)
        texture = self._textures.get(key)
        if texture is None:
            texture = self._placeholder() if path is None else self._upload_2d(self._pixels(path), srgb)
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

    def _pixels(self, path: Path) -> np.ndarray:
        return self._images.pixels(path)

    def _upload_2d(self, pixels: np.ndarray, srgb: bool):
        # GL's first row is the bottom one, and OBJ's v = 0 is the image's bottom edge.
        flipped = np.ascontiguousarray(pixels[::-1])
        height, width = flipped.shape[:2]
        texture = self.ctx.texture((width, height), 4, flipped.tobytes(),
                                   internal_format=GL_SRGB8_ALPHA8 if srgb else None)
        # Trilinear mipmapping, no anisotropic filtering: Mesa llvmpipe's anisotropic sampler
        # can stall for seconds (and has hung outright here) on some pixels, and leaving it off
        # keeps software and GPU renders filtering textures the same way.
        texture.build_mipmaps()
        return texture

    def _placeholder(self):
        pixels = placeholder_pixels()
        texture = self.ctx.texture((PLACEHOLDER_SIZE, PLACEHOLDER_SIZE), 4, pixels.tobytes())
        import moderngl

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
        texture.build_mipmaps()
        return texture

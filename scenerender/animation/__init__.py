"""Keyframe tracks: every animatable value in a scene is a ``Track``."""
from scenerender.animation.tracks import INTERPOLATIONS, Track, shared_constant

__all__ = ["INTERPOLATIONS", "Track", "shared_constant"]

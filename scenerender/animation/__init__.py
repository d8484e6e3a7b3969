"""Keyframe tracks: every animatable value in a scene is a ``Track``."""
from scenerender.animation.tracks import INTERPOLATIONS, Track, animated_keys, shared_constant

__all__ = ["INTERPOLATIONS", "Track", "animated_keys", "shared_constant"]

"""``output:``: how many frames at what rate, the file format and the frame file names."""
from __future__ import annotations

from pydantic import model_validator
from pydantic_core import PydanticCustomError

from scenerender.sinks.names import name_template_problem
from scenerender.scene.strict import StrictModel
from scenerender.scene.values import Text, choice, number

FORMATS = ("png", "jpg", "tga", "exr", "mp4", "gif")
VIDEO_FORMATS = ("mp4", "gif")


class OutputSettings(StrictModel):
    fps: number(0, 1000, lo_open=True) = 30.0
    # at most 3.4e38 (every number is), times fps at most 1000: round(duration * fps) stays finite
    duration: number(0, lo_open=True) | None = None
    frames: number(1, integer=True) | None = None  # the upper bound is Limits.frames (--limit frames=N)
    format: choice(*FORMATS) = "png"
    name: Text | None = None
    quality: number(1, 100, integer=True) = 90

    @model_validator(mode="after")
    def _check(self):
        if self.duration is not None and self.frames is not None:
            from_duration = round(self.duration * self.fps)
            if from_duration != self.frames:
                raise PydanticCustomError(
                    "frames_duration", "frames ({f}) and duration x fps ({d}) disagree; give one of them",
                    {"f": self.frames, "d": from_duration, "subpath": ("frames",)})
        if self.name is not None:
            # parsed, never formatted blindly: '{frame.__class__}' or '../x_{frame}' must
            # neither run attribute lookups nor name files outside -o
            problem = name_template_problem(self.name, self.frame_count)
            if problem is not None:
                raise PydanticCustomError("name_pattern", "{problem}; use e.g. \"frame_{frame:04d}\"",
                                          {"problem": problem, "subpath": ("name",)})
        return self

    @property
    def frame_count(self) -> int:
        if self.frames is not None:
            return self.frames
        if self.duration is not None:
            return max(1, round(self.duration * self.fps))
        return 1

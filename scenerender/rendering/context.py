"""What a pass's ``execute`` receives: the GL context, the frame, and resource lookups."""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.graph import Handle


@dataclass
class PassContext:
    gl: object          # moderngl.Context
    frame: object       # world.frame.FrameState
    scene: object       # render.scene_gpu.GpuScene
    programs: object    # gpu.shaders.ProgramCache
    features: object    # render.features.SceneFeatures
    resources: dict     # resource index -> moderngl texture/renderbuffer
    framebuffers: object  # gpu.resources.FramebufferCache
    outputs: dict       # what side-effect passes leave for the executor (e.g. "pixels")
    depth: object = None  # gpu.depth.DepthConvention of the camera passes

    def resource(self, handle: Handle):
        return self.resources[handle.resource]

    def framebuffer(self, colors, depth: Handle | None = None):
        return self.framebuffers.get(tuple(self.resource(h) for h in colors),
                                     self.resource(depth) if depth is not None else None)

    @property
    def world(self):
        return self.scene.world

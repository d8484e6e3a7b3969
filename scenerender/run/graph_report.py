"""``scenerender graph``: the render graph a scene compiles to, at the MSAA samples the GL
device at hand offers (or the scene's, where there is none), with no frame rendered."""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.errors import EnvironmentProblem
from scenerender.gpu.gl_context import create_context
from scenerender.rendering.renderer import device_samples, plan
from scenerender.world.lens import Film


@dataclass(frozen=True)
class GraphReport:
    """compiled: the CompiledGraph; samples: the MSAA samples it was planned with;
    device_max: what the device offers, None without a device."""

    scene: object
    compiled: object
    samples: int
    device_max: int | None

    def header(self, name: str) -> str:
        """One line: mode, size, the samples (and why they differ from the scene's), frames."""
        settings = self.scene.world.settings
        msaa = f"{self.samples}x MSAA" if self.samples > 1 else "no MSAA"
        if self.samples < settings.samples:
            msaa += f" ({settings.samples} asked; this device offers {self.device_max})"
        elif self.device_max is None and settings.samples > 1:
            msaa += " (no GL device to ask: a device may offer fewer)"
        film = Film.of_world(self.scene.world)
        return (f"render graph of {name}: mode {settings.mode}, {settings.size[0]}x{settings.size[1]}, {msaa}, "
                f"{self.scene.frame_count} frame(s)" + (f", {film.describe()}" if film is not None else ""))


def graph_report(scene) -> GraphReport:
    """The graph of ``scene`` (a run.session.Scene) as a render would plan it here."""
    settings = scene.world.settings
    device_max = device_max_samples()
    used = device_samples(settings.samples, device_max if device_max is not None else settings.samples)
    # a filmed frame reads back each sub-frame's linear image, as GraphRenderer plans it
    filmed = Film.of_world(scene.world) is not None
    return GraphReport(scene, plan(scene.world, settings.size, used, want_linear=filmed).compiled, used, device_max)


def device_max_samples() -> int | None:
    """The MSAA samples the default GL device offers; None when there is no device."""
    try:
        gl = create_context()
    except EnvironmentProblem:
        return None
    try:
        return gl.max_samples
    finally:
        gl.release()

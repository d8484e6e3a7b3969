"""Write open_sky.hdr, the light of benchmarks/quality/scenes/sky_contact.yaml: the sky of
make_contact_sky.py without its bright patch (a sky gradient over a dark ground, no sun),
256 x 128 equirectangular, made here from formulas (no photographed asset).

    python benchmarks/quality/scenes/make_open_sky.py
"""
from __future__ import annotations

from pathlib import Path

from make_contact_sky import open_sky_radiance, sky_image
from scenerender.world.environment_files import write_hdr

if __name__ == "__main__":
    target = Path(__file__).resolve().parent / "open_sky.hdr"
    write_hdr(target, sky_image(radiance_towards=open_sky_radiance))
    print(f"wrote {target}")

"""Each fast setting at its default beside what it costs and what the slower, closer
setting gives, from the tables' own numbers (run their scripts first: three_spheres.py,
sky_contact.py, rect_umbra.py). Writes defaults.md.

    python benchmarks/quality/defaults.py
"""
from __future__ import annotations

import json
from pathlib import Path

HERE = Path(__file__).resolve().parent


def load(name: str) -> dict:
    return json.loads((HERE / f"{name}.json").read_text())


def pct(value: float) -> str:
    return f"{value * 100:+.1f} %"


def rows() -> list[list[str]]:
    """[setting, scene, error at the default, default's ms/frame, the slower setting, its error,
    its ms/frame] a row."""
    spheres = load("three_spheres")["results"]
    split, sampled = spheres["split_sum (default)"], spheres["sampled, 32 samples (the count's default)"]
    sky = load("sky_contact")["results"]
    umbra = load("rect_umbra")
    found = [
        ["environment `specular: split_sum`", "three_spheres, copper (alone / among the spheres)",
         f"{pct(split['errors']['copper alone'])} / {pct(split['errors']['copper'])}", f"{split['ms']:.1f}",
         "`specular: sampled`, 32 samples",
         f"{pct(sampled['errors']['copper alone'])} / {pct(sampled['errors']['copper'])}", f"{sampled['ms']:.1f}"],
        ["environment visibility: 32 directions, auto blocks, half resolution", "sky_contact, ground within 10 cm / 25 cm of a box",
         f"{pct(sky['default']['errors']['foot'])} / {pct(sky['default']['errors']['contact'])}",
         f"{sky['default'].get('ms', float('nan')):.1f}", "every pixel all 32 (`visibility_interleave: 1`)",
         f"{pct(sky['32 directions, exact (every pixel all 32)']['errors']['foot'])} / "
         f"{pct(sky['32 directions, exact (every pixel all 32)']['errors']['contact'])}", "-"],
        ["environment visibility (as above)", "sky_contact, open ground / boxes' sides",
         f"{pct(sky['default']['errors']['open ground'])} / {pct(sky['default']['errors']['vertical faces'])}",
         f"{sky['default'].get('ms', float('nan')):.1f}", "64 directions, every pixel",
         f"{pct(sky['64 directions, exact']['errors']['open ground'])} / "
         f"{pct(sky['64 directions, exact']['errors']['vertical faces'])}", "-"],
        ["environment visibility (as above)", "sky_contact, blotches: RMS over the ground within 1 m of a box",
         f"{sky['default']['errors']['blotches'] * 100:.1f} %", f"{sky['default'].get('ms', float('nan')):.1f}",
         "64 directions, every pixel", f"{sky['64 directions, exact']['errors']['blotches'] * 100:.1f} %", "-"],
        ["rect light soft shadow: blockers 16, filter 32", "rect_umbra, floor's umbra leak (% of the lit floor) / band RMS",
         f"{umbra['default']['umbra leak %']:.2f} % / {umbra['default']['band RMS %']:.1f} %", f"{umbra['default']['ms']:.1f}",
         "blockers 64, filter 128",
         f"{umbra['filter 128, blockers 64']['umbra leak %']:.2f} % / {umbra['filter 128, blockers 64']['band RMS %']:.1f} %",
         f"{umbra['filter 128, blockers 64']['ms']:.1f}"],
    ]
    return found


def main() -> None:
    lines = ["# Each fast setting at its default: error against the reference beside its cost", "",
             "Made by `python benchmarks/quality/defaults.py` from three_spheres.json, sky_contact.json and",
             "rect_umbra.json (each table's own page says how its errors and times were measured: Mesa",
             "llvmpipe, 2 shared cores; ms/frame medians with the settings taking turns in one process, so",
             "compare times within a row's scene only).", "",
             "| setting (default) | measured on | error at the default | ms/frame | slower setting | its error | its ms/frame |",
             "|---|---|---|---|---|---|---|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows()]
    (HERE / "defaults.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

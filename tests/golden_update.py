"""Re-render the golden reference images: `make goldens` (every case), or
`python tests/golden_update.py NAME...` (those cases). Look at them before committing."""
from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
# this checkout's package, not whichever scenerender is installed (the script's own folder,
# tests/, is first on the path, not the repository root)
sys.path.insert(1, str(Path(__file__).resolve().parent.parent))

from PIL import Image  # noqa: E402

from golden_cases import CASES, GOLDEN_DIR, reference_path, render_case_with_ids, write_reference_ids  # noqa: E402
from scenerender.gpu.gl_context import create_context  # noqa: E402


def main() -> None:
    GOLDEN_DIR.mkdir(exist_ok=True)
    gl = create_context()
    names = sys.argv[1:] or list(CASES)
    unknown = [name for name in names if name not in CASES]
    if unknown:
        sys.exit(f"no golden case {', '.join(unknown)}; the cases: {', '.join(sorted(CASES))}")
    for name in names:
        pixels, ids = render_case_with_ids(gl, name)
        Image.fromarray(pixels).save(reference_path(name), optimize=True)
        write_reference_ids(name, ids)
        print("wrote", reference_path(name), "and its object ids")


if __name__ == "__main__":
    main()

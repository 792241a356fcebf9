"""The README's picture of a run (docs/run-paper-8x8.png): the last frame of ``navcli render`` of
paper-8x8's mission (seed 1), as a PNG. ``python docs/make_picture.py`` remakes it (about a minute)."""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

from PIL import Image

OUT = Path(__file__).resolve().parent / "run-paper-8x8.png"


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        log, gif = Path(tmp) / "run.mcap", Path(tmp) / "run.gif"
        navcli = [sys.executable, "-m", "navcli"]
        subprocess.run(navcli + ["run", "paper-8x8", "--out", str(log)], check=True)
        subprocess.run(navcli + ["render", str(log), "--out", str(gif), "--speed", "40"], check=True)
        with Image.open(gif) as im:
            im.seek(im.n_frames - 1)
            im.convert("RGB").save(OUT, optimize=True)
    print(f"wrote {OUT} ({OUT.stat().st_size} bytes)")


if __name__ == "__main__":
    main()

"""Mirror a folder into the build tree, writing only the files whose content changed.

``python mirror_tree.py SOURCE TARGET``. pip builds pinwind in a new temporary environment at
every install, so the nanobind, pin, proxsuite and Eigen files it compiles against sit at a new
path with new modification times each time, and ninja would recompile everything. Compiled
against this mirror inside the kept build folder (``build-dir`` in pyproject.toml), a reinstall
over a built checkout recompiles only what a changed dependency really changed.
"""

from __future__ import annotations

import filecmp
import os
import shutil
import sys
from pathlib import Path


def mirror(source: Path, target: Path) -> int:
    """Make ``target`` hold exactly ``source``'s files; returns how many files were written."""
    written = 0
    kept: set[Path] = set()
    for folder, folders, names in os.walk(source):
        # Python's bytecode caches are rewritten by every environment and compile nothing.
        folders[:] = [f for f in folders if f != "__pycache__"]
        out = target / Path(folder).relative_to(source)
        out.mkdir(parents=True, exist_ok=True)
        for name in names:
            src, dst = Path(folder, name), out / name
            kept.add(dst)
            # Unchanged files keep their old modification time, so nothing that includes them
            # is rebuilt.
            if dst.is_file() and filecmp.cmp(src, dst, shallow=False):
                continue
            shutil.copyfile(src, dst)
            written += 1
    for folder, _, names in os.walk(target):
        for name in names:
            if Path(folder, name) not in kept:
                Path(folder, name).unlink()
    return written


if __name__ == "__main__":
    source, target = Path(sys.argv[1]), Path(sys.argv[2])
    print(f"pinwind: {mirror(source, target)} file(s) of {source} updated in {target}")

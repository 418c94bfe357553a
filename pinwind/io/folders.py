"""Output folders: whether a folder can be made where a command will write its files.

A file where the folder (or one of its parents) should be made a command fail with a traceback
after its work (``pinwind fatigue`` with ``out`` naming a file, ``--figures`` under a file);
``folder_problem`` says it before any work is done.
"""

from __future__ import annotations

from pathlib import Path


def folder_problem(folder: Path) -> str | None:
    """What stops ``folder`` from being made (or used), or None when nothing does.

    The folder itself, or the nearest of its parents that exists, must be a folder: a file
    there is named.
    """
    for path in (folder, *folder.parents):
        if path.exists():
            if path.is_dir():
                return None
            which = "it" if path == folder else str(path)
            return f"{which} is a file, not a folder"
    return None

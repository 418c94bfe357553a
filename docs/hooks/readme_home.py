"""mkdocs hook: the site's home page is README.md, its ``docs/`` links made relative to docs/."""

from __future__ import annotations

import re
from pathlib import Path

from mkdocs.structure.files import File, Files

#: A Markdown link target into the docs folder, as the README writes it from the repository root.
DOCS_LINK = re.compile(r"\]\(docs/")


def on_files(files: Files, config) -> Files:
    """Add index.md, generated from the README (the docs folder has no index.md of its own)."""
    readme = Path(config.config_file_path).parent / "README.md"
    text = DOCS_LINK.sub("](", readme.read_text(encoding="utf-8"))
    files.append(File.generated(config, "index.md", content=text))
    return files

"""mkdocs hooks: the README is the site's home page (``index.md``) and DEVELOPERS.md its
``developers.md``, their links into ``docs/`` made relative to the site."""

from __future__ import annotations

from pathlib import Path

from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[1]
PAGES = {"index.md": ROOT / "README.md", "developers.md": ROOT / "DEVELOPERS.md"}


def on_files(files, config):
    for uri, path in PAGES.items():
        files.append(File.generated(config, uri, content=path.read_text()))
    return files


def on_page_markdown(markdown, page, config, files):
    if page.file.src_uri in PAGES:
        return markdown.replace("](docs/", "](").replace("](DEVELOPERS.md)",
                                                         "](developers.md)")
    return markdown

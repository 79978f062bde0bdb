"""Pages the documentation site generates at build time (run by the mkdocs-gen-files plugin).

Two jobs, so that the site needs no copy of anything kept elsewhere in the repository:

- an API reference page per module of ``abm``, ``models`` and ``analysis``, written from the
  packages as they are (a module added, split or renamed needs no edit here);
- the README (as "Getting started") and every repository file a page links to outside
  ``docs/`` (the models' READMEs, ``SECURITY.md``), placed under ``repo/`` in the site, with the
  relative links of every page rewritten to where their targets are in the site. The Markdown
  files keep links that work when browsing the repository; the site gets links that work there.
"""

from __future__ import annotations

import posixpath
import re
from pathlib import Path

import mkdocs_gen_files

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
PACKAGES = ("abm", "models", "analysis")
#: A Markdown link or image target: ](target) or ](target "title").
LINK = re.compile(r"(\]\()([^)\s]+)((?:\s+\"[^\"]*\")?\))")


def write_api_pages() -> None:
    """One page per public module (``::: module``) and the literate-nav SUMMARY over them."""
    nav = mkdocs_gen_files.Nav()
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            if any(p.startswith("_") and p != "__init__" for p in parts):
                continue
            if parts[-1] == "__init__":
                parts = parts[:-1]
                doc = Path(*parts, "index.md")
            else:
                doc = Path(*parts).with_suffix(".md")
            nav[parts] = doc.as_posix()
            name = ".".join(parts)
            with mkdocs_gen_files.open(Path("api", doc), "w") as page:
                page.write(f"# `{name}`\n\n::: {name}\n")
            mkdocs_gen_files.set_edit_path(Path("api", doc), path.relative_to(ROOT))
    with mkdocs_gen_files.open("api/SUMMARY.md", "w") as summary:
        summary.writelines(nav.build_literate_nav())


def site_path(repo_path: str) -> str:
    """Where a repository file (a path relative to the root) is in the site."""
    if repo_path.startswith("docs/"):
        return repo_path.removeprefix("docs/")
    if repo_path == "README.md":
        return "getting-started.md"
    return "repo/" + repo_path


def rewrite_links(text: str, repo_path: str, wanted: list[str]) -> str:
    """The page's relative links pointed at their targets' places in the site.

    ``repo_path`` is the page's own path in the repository; targets outside ``docs/`` are added
    to ``wanted`` so that they are copied into the site. A link to a missing file is left as it
    is, so that the strict build reports it.
    """
    here = posixpath.dirname(repo_path)
    page_dir = posixpath.dirname(site_path(repo_path))

    def one(match: re.Match[str]) -> str:
        target = match.group(2)
        if re.match(r"^[a-z][a-z0-9+.-]*:", target) or target.startswith(("#", "/")):
            return match.group(0)
        file, _, anchor = target.partition("#")
        resolved = posixpath.normpath(posixpath.join(here, file))
        if (ROOT / resolved).is_dir() and (ROOT / resolved / "README.md").is_file():
            resolved = posixpath.join(resolved, "README.md")
        if resolved.startswith("..") or not (ROOT / resolved).is_file():
            return match.group(0)
        if not resolved.startswith("docs/"):
            wanted.append(resolved)
        new = posixpath.relpath(site_path(resolved), page_dir or ".")
        return match.group(1) + new + ("#" + anchor if anchor else "") + match.group(3)

    return LINK.sub(one, text)


def write_linked_pages() -> None:
    """Rewrite the docs pages' links; copy in the README and every file they lead to."""
    wanted: list[str] = ["README.md"]
    for page in sorted(DOCS.glob("*.md")):
        repo_path = page.relative_to(ROOT).as_posix()
        text = rewrite_links(page.read_text(encoding="utf-8"), repo_path, wanted)
        with mkdocs_gen_files.open(site_path(repo_path), "w") as out:
            out.write(text)
    done: set[str] = set()
    while wanted:
        repo_path = wanted.pop()
        if repo_path in done:
            continue
        done.add(repo_path)
        source = ROOT / repo_path
        if repo_path.endswith(".md"):
            text = rewrite_links(source.read_text(encoding="utf-8"), repo_path, wanted)
            with mkdocs_gen_files.open(site_path(repo_path), "w") as out:
                out.write(text)
            mkdocs_gen_files.set_edit_path(site_path(repo_path), repo_path)
        else:
            with mkdocs_gen_files.open(site_path(repo_path), "wb") as out:
                out.write(source.read_bytes())


write_api_pages()
write_linked_pages()

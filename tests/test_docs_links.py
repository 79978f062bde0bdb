"""The README stays a short page for users, and no relative link in it or in docs/ is broken.

The README's measurement tables moved to docs/ pages; these checks keep it that way, and keep
every relative link (pages, models' READMEs, pictures, scripts) pointing at a file that exists,
as GitHub and the documentation site both need.
"""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
PAGES = sorted((ROOT / "docs").glob("*.md"))
#: A Markdown link or image: [text](target) or ![alt](target "title").
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
MAX_README_LINES = 200


def relative_links(page: Path) -> list[str]:
    """The page's link targets that name a file in the repository (no URL, no bare anchor)."""
    text = re.sub(r"```.*?```", "", page.read_text(encoding="utf-8"), flags=re.DOTALL)
    return [
        target
        for target in LINK.findall(text)
        if not re.match(r"^[a-z][a-z0-9+.-]*:", target) and not target.startswith("#")
    ]


def test_readme_is_at_most_200_lines():
    lines = README.read_text(encoding="utf-8").count("\n")
    assert lines <= MAX_README_LINES, f"README.md has {lines} lines; move detail to docs/"


def test_the_link_finder_sees_links_images_and_skips_urls(tmp_path):
    page = tmp_path / "p.md"
    page.write_text(
        '[a](x.md) ![b](img/y.png "t") [c](https://e.org/z.md) [d](#top) [e](w.md#part)\n'
        "```sh\n[f](in-code.md)\n```\n",
        encoding="utf-8",
    )
    assert relative_links(page) == ["x.md", "img/y.png", "w.md#part"]


@pytest.mark.parametrize("page", [README, *PAGES], ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_relative_link_names_an_existing_file(page):
    assert page.is_file()
    missing = []
    for target in relative_links(page):
        path = (page.parent / target.partition("#")[0]).resolve()
        if not path.exists():
            missing.append(target)
        elif not path.is_relative_to(ROOT):
            missing.append(f"{target} (outside the repository)")
    assert not missing, f"{page.relative_to(ROOT)}: broken links {missing}"


def test_the_readme_links_every_docs_page_it_sends_users_to():
    """The README's 'Where to go next' reaches the pages that took over its old sections."""
    targets = {t.partition("#")[0] for t in relative_links(README)}
    for page in ("reproduction", "performance", "history", "usage", "adding-a-model"):
        assert f"docs/{page}.md" in targets, f"README.md does not link docs/{page}.md"

"""The framework is generic and the repository carries its own knowledge.

``abm/`` names no paper and no author (papers' worlds, maps and constants live with the models
that use them, or in ``models/environments/``), and no file cites "spec §", a reading users do
not have: code and docs cite the paper's own section, figure or equation, or the model's README.
"""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: The papers' authors, their institution, the classic models' authors, citations and the word
#: "paper" itself.
PAPER_NAMES = re.compile(
    r"stirling|arnaldo|purohit|saska|alunni|\bwpi\b|reynolds|vicsek|kennedy|eberhart"
    r"|rappaport|et al\b|\b(19|20)\d\d\b|\bpapers?\b",
    re.IGNORECASE,
)

#: Files still citing "spec §" until their rewrite lands (empty this list then; the README is
#: being rewritten).
SPEC_PENDING: set[str] = set()

SPEC_REFERENCE = re.compile(
    r"§|shared/spec|SPEC\.md|\bspec [A-Z]\d|\bspec\W+\w+\.md"
    r"|\bour spec\b|\bthe spec's|\bfrom the spec\b|(?-i:\bSPEC [A-Z]\b)",
    re.IGNORECASE,
)


def _files(top: Path, suffixes: tuple[str, ...]) -> list[Path]:
    skip = {".venv", ".git", "out", "node_modules", "__pycache__"}
    return [
        p
        for p in top.rglob("*")
        if p.suffix in suffixes and p.is_file() and not skip.intersection(p.relative_to(ROOT).parts)
    ]


def _hits(paths: list[Path], pattern: re.Pattern) -> list[str]:
    return [
        f"{p.relative_to(ROOT)}:{n}: {line.strip()}"
        for p in paths
        for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
        if pattern.search(line)
    ]


def test_the_framework_names_no_paper_and_no_author():
    hits = _hits(_files(ROOT / "abm", (".py", ".md", ".j2", ".toml")), PAPER_NAMES)
    assert not hits, "abm/ names a paper or an author:\n" + "\n".join(hits)


@pytest.mark.parametrize("suffixes", [(".py",), (".md",), (".toml",)])
def test_nothing_cites_our_private_spec(suffixes):
    paths = [p for p in _files(ROOT, suffixes) if str(p.relative_to(ROOT)) not in SPEC_PENDING]
    hits = _hits(paths, SPEC_REFERENCE)
    hits = [h for h in hits if not h.startswith("tests/test_no_paper_names.py:")]
    assert not hits, 'cites "spec" (cite the paper or the model\'s README):\n' + "\n".join(hits)

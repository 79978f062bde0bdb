"""Every script in examples/ runs as a newcomer runs it (in a fresh folder) and prints what its
saved expected output ``examples/<name>.out`` says (numbers to 4 significant digits)."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("*.py"))
NUMBER = re.compile(r"-?\d[\d,]*\.?\d*(?:e[-+]?\d+)?")


def _normalised(text: str) -> list[str]:
    """Lines with every number rounded to 4 significant digits (platform-proof)."""

    def rounded(match: re.Match) -> str:
        value = float(match.group().replace(",", ""))
        return f"{value:.4g}"

    return [NUMBER.sub(rounded, line.rstrip()) for line in text.strip().splitlines()]


def test_every_example_has_an_expected_output():
    assert EXAMPLES, "no examples"
    missing = [p.name for p in EXAMPLES if not p.with_suffix(".out").is_file()]
    assert not missing, f"examples without a saved expected output: {missing}"


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_example_prints_its_expected_output(script, tmp_path):
    result = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    assert _normalised(result.stdout) == _normalised(script.with_suffix(".out").read_text())
    written = [line.split()[1] for line in result.stdout.splitlines() if line.startswith("wrote ")]
    assert written and all((tmp_path / path).is_file() for path in written)

"""A MkDocs hook: the docstrings' Sphinx roles shown as code, not as literal ``:class:`` text.

The docstrings cross-reference with reST roles (``:class:`~abm.comms.radio.Shadowing```), which
the API pages' renderer leaves as ``:class:`` followed by the code. This hook drops the role and,
for a ``~`` reference, keeps only the last name, as Sphinx shows it.
"""

import re

ROLE = re.compile(r":(?:class|func|meth|mod|data|attr|exc|obj):<code>(~?)([^<]+)</code>")


def _shown(match: re.Match) -> str:
    tilde, target = match.groups()
    name = target.rsplit(".", 1)[-1] if tilde else target
    return f"<code>{name}</code>"


def on_page_content(html: str, **kwargs) -> str:
    """Replace every role-prefixed code span of a page by the code span alone."""
    return ROLE.sub(_shown, html)

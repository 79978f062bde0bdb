"""The one HTML layer of the project's reports: Jinja2 templates, embedded figures, tables.

Both reports (``abm report`` of a sweep, ``abm fit`` of a model against its macroscopic
recurrence) extend ``templates/base.html.j2`` (page, styles, header) and are written as one
self-contained file: figures are embedded as PNG data, tables are inline.
"""

import base64
import html
import io
from pathlib import Path

import jinja2
import pandas as pd

__all__ = ["figure_data", "image_data", "render_page", "table"]

_ENV = jinja2.Environment(
    loader=jinja2.PackageLoader("analysis.html", "templates"),
    autoescape=jinja2.select_autoescape(["html", "j2"]),
    undefined=jinja2.StrictUndefined,
    trim_blocks=True,
    lstrip_blocks=True,
)


def render_page(template: str, path: str | Path, **context: object) -> Path:
    """Render ``template`` with ``context`` into the file ``path``; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(_ENV.get_template(template).render(**context))
    return path


def image_data(path: str | Path) -> str:
    """A PNG file as a ``data:`` URI (for ``<img src=...>``)."""
    return "data:image/png;base64," + base64.b64encode(Path(path).read_bytes()).decode()


def figure_data(fig, dpi: int = 90) -> str:
    """A matplotlib figure as a PNG ``data:`` URI."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode()


def table(df: pd.DataFrame, digits: int = 3, text_columns: tuple[str, ...] = ()) -> str:
    """An HTML table of ``df``: numbers to ``digits`` significant digits, text left-aligned.

    Returned as markup (safe to insert unescaped: every cell is escaped here).
    """
    heads = "".join(
        f'<th class="{"text" if c in text_columns else ""}">{html.escape(str(c))}</th>'
        for c in df.columns
    )
    rows = []
    for values in df.itertuples(index=False):
        cells = []
        for column, value in zip(df.columns, values, strict=True):
            kind = "text" if column in text_columns or isinstance(value, str) else ""
            cells.append(f'<td class="{kind}">{html.escape(_cell(value, digits))}</td>')
        rows.append(f"<tr>{''.join(cells)}</tr>")
    return jinja2.utils.markupsafe.Markup(
        f"<table><thead><tr>{heads}</tr></thead><tbody>{''.join(rows)}</tbody></table>"
    )


def _cell(value: object, digits: int) -> str:
    if value is None or (isinstance(value, float) and value != value):
        return "\u2013"
    if isinstance(value, bool):
        return str(value)
    if isinstance(value, int):
        return f"{value:,}"
    if isinstance(value, float):
        return f"{value:,.{digits}g}" if abs(value) < 1e6 else f"{value:.{digits}g}"
    return str(value)

"""The Solara app ``abm viz`` serves: the page of the model named in ``ABM_VIZ_MODEL``.

The variable holds a registered model name or ``"module:Class"``. The page is the model's own
(``page`` in the module its ``APP`` names) or, for a model without one, the default page of
:func:`abm.viz.page.make_page`. Needs the ``viz`` extra.
"""

import importlib
import os
from functools import cache

from abm.errors import ContractError
from abm.registry import model_class, name_of

__all__ = ["ENV_VAR", "page_of"]

#: Environment variable naming the model the app shows.
ENV_VAR = "ABM_VIZ_MODEL"


@cache
def page_of(model: str):
    """The Solara ``Page`` component of a model (its app's ``page``, or the default page)."""
    from abm.viz.page import make_page

    cls = model_class(model)
    if cls.APP is None:
        return make_page(cls, name=name_of(cls) or model)
    module = importlib.import_module(cls.APP)
    page = getattr(module, "page", None)
    if page is None:
        raise ContractError(f"{cls.APP} (the APP of {cls.__name__}) defines no 'page'")
    return page


def __getattr__(name: str):
    if name == "Page":
        return page_of(os.environ.get(ENV_VAR, "beacon-explorer"))
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

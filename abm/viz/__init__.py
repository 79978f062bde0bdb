"""Visualisation of swarm models: scene drawing (matplotlib) and the SolaraViz page.

``Scene``, ``SceneView``, ``scene_of`` and ``view_of`` need only matplotlib. ``make_page`` (and
the Solara components) need the ``viz`` extra and are imported on first use, so
``import abm.viz`` works without it.
"""

from abm.scene import Scene, scene_of
from abm.viz.scene import SceneView, view_of

__all__ = ["Scene", "SceneView", "make_page", "scene_of", "view_of"]


def __getattr__(name: str):
    if name == "make_page":
        from abm.viz.page import make_page

        return make_page
    raise AttributeError(f"module 'abm.viz' has no attribute {name!r}")

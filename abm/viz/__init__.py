"""Visualisation of swarm models: scene drawing (matplotlib) and the SolaraViz page.

``Scene``, ``SceneView`` and ``scene_of`` need only matplotlib. ``make_page`` (and the Solara
components) need the ``viz`` extra and are imported on first use, so ``import abm.viz`` works
without it.
"""

from abm.viz.scene import Scene, SceneView, scene_of, state_colour

__all__ = ["Scene", "SceneView", "make_page", "scene_of", "state_colour"]


def __getattr__(name: str):
    if name == "make_page":
        from abm.viz.page import make_page

        return make_page
    raise AttributeError(f"module 'abm.viz' has no attribute {name!r}")

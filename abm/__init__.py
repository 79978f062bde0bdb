"""swarm-abm's framework: what a model is built from, in one import.

``from abm import SwarmModel, SwarmParams, param, Robot, Arena, ...`` gives the public API a
model needs; each name lives in the module named beside it below, where its documentation is.
The names are imported when first used, so ``import abm.errors`` (which the command line does
before any heavy work) does not load the simulation modules and their compiled kernels.
"""

import importlib
from typing import TYPE_CHECKING

#: Public name -> the module that defines it.
_WHERE = {
    # a model and its parameters
    "SwarmModel": "abm.model",
    "SwarmParams": "abm.params",
    "param": "abm.params",
    # robots, their world and their motion
    "Robot": "abm.robot",
    "Arena": "abm.arena",
    "FlightParams": "abm.physics",
    "Physics": "abm.physics",
    "CoverageRaster": "abm.coverage",
    "StateStyle": "abm.styles",
    "Layer": "abm.styles",
    # communication
    "CommNetwork": "abm.comms",
    "GradientFlood": "abm.comms",
    "MessageLog": "abm.comms",
    "Shadowing": "abm.comms",
    # what a model declares for the reports and fits
    "Published": "abm.published",
    "Claim": "abm.published",
    "Censored": "abm.published",
    "MacroSpec": "abm.published",
    "ReportLayout": "abm.published",
    # errors a user sees as one line
    "ConfigError": "abm.errors",
    "HookError": "abm.errors",
}

__all__ = [
    "Arena",
    "Censored",
    "Claim",
    "CommNetwork",
    "ConfigError",
    "CoverageRaster",
    "FlightParams",
    "GradientFlood",
    "HookError",
    "Layer",
    "MacroSpec",
    "MessageLog",
    "Physics",
    "Published",
    "ReportLayout",
    "Robot",
    "Shadowing",
    "StateStyle",
    "SwarmModel",
    "SwarmParams",
    "param",
]

if TYPE_CHECKING:  # for type checkers and editors: the same names, imported eagerly
    from abm.arena import Arena
    from abm.comms import CommNetwork, GradientFlood, MessageLog, Shadowing
    from abm.coverage import CoverageRaster
    from abm.errors import ConfigError, HookError
    from abm.model import SwarmModel
    from abm.params import SwarmParams, param
    from abm.physics import FlightParams, Physics
    from abm.published import Censored, Claim, MacroSpec, Published, ReportLayout
    from abm.robot import Robot
    from abm.styles import Layer, StateStyle


def __getattr__(name: str) -> object:
    """Import a public name from its module on first use (PEP 562)."""
    if name not in _WHERE:
        raise AttributeError(f"module 'abm' has no attribute {name!r}")
    value = getattr(importlib.import_module(_WHERE[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})

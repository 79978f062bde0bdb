"""Wander/beacon UAV swarm with virtual stigmergy (Arnaldo et al. 2018)."""

from models.stigmergy.model import StigmergyModel
from models.stigmergy.params import DEFAULTS, StigmergyParams

__all__ = ["DEFAULTS", "StigmergyModel", "StigmergyParams"]

"""Wander/beacon UAV swarm with virtual stigmergy (Arnaldo et al. 2018), SPEC B."""

from models.stigmergy.model import StigmergyModel
from models.stigmergy.params import (
    DEFAULTS,
    PAPER_LAMBDAS,
    PAPER_TABLE1,
    PAPER_TABLE2,
    StigmergyParams,
)

__all__ = [
    "DEFAULTS",
    "PAPER_LAMBDAS",
    "PAPER_TABLE1",
    "PAPER_TABLE2",
    "StigmergyModel",
    "StigmergyParams",
]

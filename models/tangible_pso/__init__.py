"""Tangible PSO: swarm distribution and deployment for surveillance by micro-aerial vehicles,
with motion planning inside the optimiser (Saska et al. 2016).
"""

from models.tangible_pso.agents import MAV, VirtualMAV
from models.tangible_pso.model import TangiblePSOModel
from models.tangible_pso.params import TangiblePSOParams

__all__ = ["MAV", "TangiblePSOModel", "TangiblePSOParams", "VirtualMAV"]

"""SugarMap: location-less coverage by a micro-aerial swarm (Purohit et al. 2013), with its
random-walk and OMSTC baselines.
"""

from models.sugarmap.model import SugarMapModel
from models.sugarmap.params import DEFAULTS, SugarMapParams

__all__ = ["DEFAULTS", "SugarMapModel", "SugarMapParams"]

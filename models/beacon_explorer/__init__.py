"""Beacon/explorer incremental deployment (Stirling et al. 2010)."""

from models.beacon_explorer.model import BeaconExplorerModel
from models.beacon_explorer.params import DEFAULTS, SWARM_SIZE, BeaconExplorerParams

__all__ = ["BeaconExplorerModel", "BeaconExplorerParams", "DEFAULTS", "SWARM_SIZE"]

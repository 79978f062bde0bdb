"""Hierarchical swarm topology with bubble coverage (Alunni et al., WPI 2011)."""

from models.hierarchy.model import HierarchyModel
from models.hierarchy.params import HierarchyParams

__all__ = ["HierarchyModel", "HierarchyParams"]

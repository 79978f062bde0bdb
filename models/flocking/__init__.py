"""The ABMFrameworksComparison flocking model (boids on a periodic square) on the framework."""

from models.flocking.agents import Bird
from models.flocking.model import FlockingModel
from models.flocking.params import LARGE, SMALL, FlockingParams

__all__ = ["LARGE", "SMALL", "Bird", "FlockingModel", "FlockingParams"]

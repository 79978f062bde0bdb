"""The unit and meaning of each key of the flocking model's summary; the common keys are
documented in :data:`abm.units.COMMON`.
"""

from abm.units import Quantity

__all__ = ["SUMMARY_UNITS"]

SUMMARY_UNITS = {
    "updates": Quantity("count", "update steps run"),
    "polarisation": Quantity(
        "1", "|mean unit velocity| at the last step (0: headings at random, 1: all aligned)"
    ),
    "mean_neighbours": Quantity("count", "mean neighbours of a bird at the last step"),
}

"""What Alunni et al. (2011) publish about the hierarchical swarm: no numbers (spec §4.3), the
claims C1-C14 of spec §4.4 with their tests, and the paper-style figure layout (mean scan area
and drive distance per scout and per worker against the total number of robots N).
"""

from abm.published import ReportLayout

__all__ = ["CLAIMS", "PUBLISHED", "REPORT"]

#: The report publishes no numeric result (its figures carry no values in the text).
PUBLISHED: list = []
CLAIMS: list = []
REPORT = ReportLayout(
    x="N",
    metrics=("scout_scan_area", "worker_scan_area", "scout_drive", "worker_drive"),
)

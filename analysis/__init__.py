"""Everything after (or around) a run: sweeps, statistics, macroscopic models, figures, reports."""

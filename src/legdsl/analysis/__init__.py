"""What a run measured: gait metrics (Table 2) and plots."""

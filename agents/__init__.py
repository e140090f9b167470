"""Task agents, the manager and the baseline particle system (pure, numpy only)."""

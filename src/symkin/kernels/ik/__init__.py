"""IK plans and settings: the single source both the Python and the C solvers read."""

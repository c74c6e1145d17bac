"""Numeric consumers of the derived model and the generated code: evaluation, inverse
kinematics, trajectory optimisation, plots."""

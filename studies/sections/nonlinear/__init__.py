"""The nonlinear section of a study."""

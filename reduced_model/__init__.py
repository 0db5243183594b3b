"""The paper's 3-DOF shimmy model, its pressure-dependent tyre and a bifurcation toolkit."""

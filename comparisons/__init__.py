"""Both models side by side: the shimmy command, reference data, plots, benchmarks."""

"""Studies over both models: kick thresholds, peaks of continued cycles, steady amplitudes by simulation, growth
rates against the linearisation, and the shifts of each assumption of the reduced model."""

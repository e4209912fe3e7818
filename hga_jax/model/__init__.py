"""The model: scenario, geometry, tangents, decoding, fitness, the exact solver and the float64 path."""

//! Particle swarm optimisation of knot vectors: the integrated fitting-and-fairing method.

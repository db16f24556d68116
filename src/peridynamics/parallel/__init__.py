"""Decomposed (MPI) runs: partition, local clouds, the MPI communicator, the session."""

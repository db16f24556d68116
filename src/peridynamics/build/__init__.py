"""Build: a deck into the objects of a simulation."""

"""Deck -> objects: geometry, bonds, materials, damage, loads, solver, bodies, the
decomposed (MPI) build and set-up errors (the build layer; it knows decks, the layers
below know none)."""

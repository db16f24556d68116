"""Rigid bodies: analytic shapes (:mod:`peridynamics.bodies.shapes`) and their contact
with deformable points (:mod:`peridynamics.bodies.contact`)."""

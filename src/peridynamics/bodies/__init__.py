"""Rigid bodies: analytic shapes (:mod:`peridynamics.bodies.shapes`) and their contact
with deformable points (:mod:`peridynamics.bodies.rigid_contact_forces`)."""

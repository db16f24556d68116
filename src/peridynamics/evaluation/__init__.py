"""The evaluator: the physics order of one force evaluation
(:class:`~peridynamics.evaluation.model.Model`, exported here as ``Model``, in
:mod:`peridynamics.evaluation.model`; what it measures: :mod:`peridynamics.evaluation.measures`)
and short-range contact between points (:mod:`peridynamics.evaluation.short_range_contact`)."""

from peridynamics.evaluation.model import Model

__all__ = ["Model"]

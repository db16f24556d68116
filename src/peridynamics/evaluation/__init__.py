"""The evaluator: the physics order of one force evaluation
(:class:`~peridynamics.evaluation.evaluator.Evaluator`, exported here as ``Evaluator``, in
:mod:`peridynamics.evaluation.evaluator`; what it measures: :mod:`peridynamics.evaluation.measures`)
and short-range contact between points (:mod:`peridynamics.evaluation.short_range_contact`)."""

from peridynamics.evaluation.evaluator import Evaluator

__all__ = ["Evaluator"]

"""The assessment of a real object: stripes, fragility functions and the isolation design search.

* :mod:`~isorock.assessment.stripes`: the object (:class:`AssessedObject`), its full runs at every
  intensity level (multiple-stripe analysis), the per-stripe counts and displacements, the fitted
  fragilities and the values at the design levels;
* :mod:`~isorock.assessment.fragility`: lognormal fragility functions fitted by maximum likelihood
  (Baker 2015);
* :mod:`~isorock.assessment.design`: the isolation design search over a grid of isolators;
* :mod:`~isorock.assessment.summary`: what the assessment tells a user, from the store: the
  ``isorock assess --json`` object, the plain-language conclusions and the report's summary table.

It may import the engine (:mod:`isorock.physics.engine`, through its batch interface), the model, the
excitation and the store; never the workflow (:mod:`isorock.pipeline`), the figures or the command
line. The workflow's assessment jobs are :mod:`isorock.jobs.assessment`, its figures
:mod:`isorock.figures.assessment`, its command ``isorock assess`` :mod:`isorock.cli.assessment`.
"""

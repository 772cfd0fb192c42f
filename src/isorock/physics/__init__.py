"""The physics: the rigid body and the uniform block, the bases (no isolation, linear, friction pendulum),
the excitation, the results, the compiled engine and the searches and maps built on it.

Modules, each importing only those before it: :mod:`~.body` (a rigid body's geometry, inertia and
impacts), :mod:`~.model` (the uniform block of the paper, the isolators, the system),
:mod:`~.excitation` (pulses and ground motions), :mod:`~.result` (one analysis), :mod:`~.engine`
(the numba kernel behind a validating :func:`~isorock.physics.engine.simulate`, and the independent
oracle of the tests), :mod:`~.overturning` (the minimum overturning acceleration) and
:mod:`~.regime_maps` (response-regime maps). Nothing here reads a file or knows of the workflow.
"""

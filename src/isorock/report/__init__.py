"""The report: its pages (:mod:`~.build`), the landing page (:mod:`~.landing`) and the Jinja2
templates that lay them out (:mod:`~.html`, ``templates/``); the assessment's words are
:mod:`isorock.assessment.summary`.
"""

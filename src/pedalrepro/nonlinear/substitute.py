"""Substitute non-linear model HS: a rigid-rider body plus a linear correction.

The thesis's model HS (hybrid bicycle, straight arms) carries the passive upper body of Schwab
et al. (2012) with the hands on the handlebars (Sec 3.1.1.2, Fig 3.4). Straight arms with ball
joints at shoulder and hand lock the steering of a rigid trunk, so its loop closure depends on
choices the text leaves open (the SPACAR element list is not published). This project
therefore uses a documented substitute that is faithful in the linear limit
(``data/parameters/nonlinear_models.yaml``, book page "Deviations and ambiguities"). CF (flexed
arms, hinged at shoulders and elbows) is built with its own arm loops
(:mod:`pedalrepro.nonlinear.arms`); the machinery below would serve any model whose yaml entry
has a ``substitute`` key::

    substitute = rigid-rider model of the same bicycle (the HR / CR bodies, moving legs for NP)
                 + dM q'' + v dC1 q' + (g dK0 + v^2 dK2) q  on the roll and steer equations,
    d* = Appendix B matrices (Eq B.2-B.17) - the linearisation of that rigid-rider body.

Its linearisation equals Appendix B to round-off (tested); its non-linear terms are those of the
rigid-rider Whipple model.
"""

from __future__ import annotations

from functools import cache

import numpy as np

from .. import params
from .bodies import legs_fixed, model_bodies
from .numeric import NonlinearModel, benchmark_matrices
from .settings import model_options, model_spec

MATRICES: tuple[str, ...] = ("M", "C1", "K0", "K2")


def substitute_spec(model: str) -> dict | None:
    """The ``substitute`` entry of ``nonlinear_models.yaml`` for ``model`` (None: own bodies)."""
    return model_spec(model).get("substitute")


def is_substitute(model: str) -> bool:
    """True for the substitute models (HS)."""
    return substitute_spec(model) is not None


@cache
def body_linearisation(model: str) -> dict[str, np.ndarray]:
    """``M, C1, K0, K2`` of the model's rigid-rider body alone (legs fixed at crank angle 0).

    For HR/CR (and the benchmark) this is the model's own linearisation; for a substitute it is
    the linearisation of the body it is built on, before the correction.
    """
    spec = substitute_spec(model)
    body = spec["body_of"] if spec else model
    return benchmark_matrices(NonlinearModel(legs_fixed(body), model_options(body),
                                             arm_parameters=model_bodies(body)[1]))


@cache
def linear_correction(model: str) -> dict[str, np.ndarray] | None:
    """The correction matrices ``d*`` of a substitute (None for a model built from its bodies).

    ``d* = Appendix B - body_linearisation`` (benchmark form, Eq 3.1), so that the substitute's
    linearisation is Appendix B (the thesis's own linear model).
    """
    spec = substitute_spec(model)
    if spec is None:
        return None
    if spec.get("linear_limit") != "appendix_b":
        raise ValueError(f"substitute {model}: unknown linear_limit {spec.get('linear_limit')!r}")
    target = params.appendix_b_model(model)
    body = body_linearisation(model)
    return {k: getattr(target, k) - body[k] for k in MATRICES}

"""The five report statuses and what each one means (the one definition; README and the report
page quote it).

A status is only as strong as its check:

``reproduced``
    A published number matched to its printed precision (``rounds_to``; ``equals`` on a number),
    or within a tolerance of at most 10 % of the published value whose reason does not come from
    the result (``abs``, ``relative``, ``half_step``, ``max_difference`` with a bound of at most
    :data:`PRECISE_LIMIT`).
``consistent``
    The claim holds, but it is a range, a one-sided bound, an order of magnitude, a tolerance wider
    than 10 % or a statement in words: a value far from the thesis's could pass it too.
``calibrated``
    The value is a target or an input of the project's own fit (the non-linear frames calibrated
    to Appendix B, an input chosen with this published number in view that the row no longer
    matches when the input is moved within its uncertainty): it agrees by construction and is
    not evidence.
``differs``
    The check fails: a finding, explained in the row's note and on the deviations page.
``not reproducible here``
    The thesis's means (its data, its code) are not available; the row says what is missing.
"""

from __future__ import annotations

__all__ = [
    "REPRODUCED", "CONSISTENT", "CALIBRATED", "DIFFERS", "NOT_REPRODUCIBLE", "STATUSES",
    "PRECISE_LIMIT", "MEANING",
]

REPRODUCED = "reproduced"
CONSISTENT = "consistent"
CALIBRATED = "calibrated"
DIFFERS = "differs"
NOT_REPRODUCIBLE = "not reproducible here"
#: The allowed statuses, strongest evidence first.
STATUSES: tuple[str, ...] = (REPRODUCED, CONSISTENT, CALIBRATED, DIFFERS, NOT_REPRODUCIBLE)
#: A tolerance (relative to the published value) up to which a passing check is a reproduction.
PRECISE_LIMIT = 0.10

#: One sentence per status (the report page's legend, README's list).
MEANING: dict[str, str] = {
    REPRODUCED: "a published number matched to its printed precision, or within a tolerance of "
                "at most 10 % that does not come from the result",
    CONSISTENT: "the claim holds, but it is a range, a bound, an order of magnitude, a tolerance "
                "wider than 10 % or a statement in words, so a value far off could pass it too",
    CALIBRATED: "the value is a target or an input of the project's own fit: it agrees by "
                "construction and is not evidence",
    DIFFERS: "the check fails: a finding, explained in the note and on the deviations page",
    NOT_REPRODUCIBLE: "the thesis's means (data, code) are not available here",
}

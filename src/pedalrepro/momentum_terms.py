"""Names of the three terms of the equations of motion that the momentum approach neglects
(thesis Eq 3.29, Sec 3.2.3.1): a leaf module (no imports), so that the neglected-momenta figures
labelling them (:func:`pedalrepro.figures.linear.figs_neglected_momenta`) do not depend on the
physics of :mod:`pedalrepro.momentum`.
"""

__all__ = ["NEGLECTED_TERMS"]

#: The three neglected terms of Eq 3.29, in the order of
#: :func:`pedalrepro.momentum.neglected_momenta_ratios`.
NEGLECTED_TERMS: tuple[str, ...] = ("v C1 q", "g K0 int q dt", "v^2 K2 int q dt")

"""Skips that CI turns into failures.

A test whose input is missing on a developer's machine (the real treadmill subset beside the
clone, a C compiler) skips with the reason; in CI, where ``.ci/run`` sets the flag to ``1``, the
same test fails instead, so a missing input can never pass as a skip there.

=========================  =====================================================
flag                       what it requires
=========================  =====================================================
``PEDALREPRO_REQUIRE_REAL``  the real measurements beside the clone: the public subset
                           (``../shared/reference/real-mocap``) and Moore's measured
                           spectra (``../shared/reference/moore-spectra``)
``PEDALREPRO_REQUIRE_CC``    a C compiler for the compiled right-hand sides
``PEDALREPRO_REQUIRE_BOOK``  the book's offline MathJax (``node_modules``, ``npm ci``)
=========================  =====================================================

The two end-to-end tests with their own system requirements keep their own flags, in the same
way: ``PEDALREPRO_REQUIRE_BROWSER`` (tests/workflow/test_book_browser.py) and
``PEDALREPRO_REQUIRE_CLUSTER`` (tests/workflow/test_cluster.py). No other test skips
(tests/test_lint.py).
"""

from __future__ import annotations

import os

import pytest

REAL = "PEDALREPRO_REQUIRE_REAL"
CC = "PEDALREPRO_REQUIRE_CC"
BOOK = "PEDALREPRO_REQUIRE_BOOK"


def required(flag: str) -> bool:
    """Whether ``flag`` is set to ``1`` (CI)."""
    return os.environ.get(flag) == "1"


def skip_unless_required(flag: str, reason: str) -> None:
    """Skip with ``reason``, or fail with it when ``flag`` is ``1``."""
    if required(flag):
        pytest.fail(f"{reason} ({flag}=1: this input is required here)")
    pytest.skip(reason)

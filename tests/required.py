"""Skips that CI turns into failures.

A test whose input is missing on a developer's machine (the real treadmill subset beside the
clone, a C compiler) skips with the reason; in CI, where ``.ci/run`` sets the flag to ``1``, the
same test fails instead, so a missing input can never pass as a skip there.

=========================  =====================================================
flag                       what it requires
=========================  =====================================================
``PEDALREPRO_REQUIRE_REAL``  the real public subset (``../shared/reference/real-mocap``)
``PEDALREPRO_REQUIRE_CC``    a C compiler for the compiled right-hand sides
=========================  =====================================================
"""

from __future__ import annotations

import os

import pytest

REAL = "PEDALREPRO_REQUIRE_REAL"
CC = "PEDALREPRO_REQUIRE_CC"


def required(flag: str) -> bool:
    """Whether ``flag`` is set to ``1`` (CI)."""
    return os.environ.get(flag) == "1"


def skip_unless_required(flag: str, reason: str) -> None:
    """Skip with ``reason``, or fail with it when ``flag`` is ``1``."""
    if required(flag):
        pytest.fail(f"{reason} ({flag}=1: this input is required here)")
    pytest.skip(reason)

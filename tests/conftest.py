"""Shared pytest fixtures."""

from __future__ import annotations

import pytest

from pedalrepro import params


@pytest.fixture(scope="session")
def published() -> dict:
    """The thesis's published numbers (expected values only)."""
    return params.published()

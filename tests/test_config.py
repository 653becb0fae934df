"""The configuration schema (pedalrepro.config): both shipped profiles validate, a value outside
the schema is a clear error naming its key. (Hostile values: tests/test_hostile_config.py.)"""

from __future__ import annotations

import numpy as np
import pytest

from pedalrepro import config, paths


def test_both_config_profiles_validate():
    full = config.load()
    quick = config.load(None, paths.CONFIG / "quick.yaml")
    assert full["profile"] == "thesis" and quick["profile"] == "quick"
    # the thesis grids: 10302 particular-solution points (Sec 3.1.2.2.1)
    lin = full["linear"]
    n_w = int(np.floor(lin["ps_omega_max_rad_s"] / lin["ps_omega_step_rad_s"] + 1e-9)) + 1
    n_v = int(round(lin["ps_speed_max_m_s"] / lin["ps_speed_step_m_s"])) + 1
    assert n_w * n_v == 10302


@pytest.mark.parametrize(
    "key, value, message",
    [
        (("seed",), -1, "minimum"),
        (("linear", "rtol"), 0.5, "maximum"),
        (("section2", "cadence_rpm"), "sixty", "not of type"),
        (("profile",), "huge", "is not one of"),
    ],
)
def test_config_outside_schema_is_a_clear_error(key, value, message):
    cfg = config.load()
    target = cfg
    for k in key[:-1]:
        target = target[k]
    target[key[-1]] = value
    with pytest.raises(config.ConfigError, match=message) as info:
        config.validate(cfg)
    assert ".".join(key) in str(info.value)

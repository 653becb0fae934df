"""The time-solution file (pedalrepro.timesolution): round trip, key check, chunk join."""

from __future__ import annotations

import zipfile

import numpy as np
import pytest

from pedalrepro import timesolution


def arrays(method: str = "LA", n_v: int = 4, n_w: int = 3, n_t: int = 11) -> dict:
    """A small time-solution set in the writers' key order (values from a seeded generator)."""
    rng = np.random.default_rng(7)
    grid = (n_v, n_w)
    out = dict(speed_m_s=np.linspace(0.0, 10.0, n_v), omega_rad_s=np.linspace(0.5, 4 * np.pi, n_w),
               roll_amp_rad=rng.random(grid), steer_amp_rad=rng.random(grid),
               t_end_s=np.full(grid, 10.0), fell=rng.random(grid) > 0.5, method=method,
               model="HS", harmonics=np.array([1, 3, 5]), sample_rate_hz=100.0,
               example_speed_m_s=rng.random(6), example_omega_rad_s=rng.random(6),
               example_t_s=np.linspace(0.0, 0.1, n_t), example_roll_rad=rng.random((6, n_t)),
               example_steer_rad=rng.random((6, n_t)), example_t_end_s=np.full(6, 0.1),
               example_fell=np.zeros(6, bool), series_speed_m_s=np.full(6, 5.0),
               series_omega_rad_s=rng.random(6), series_roll_rad=rng.random((6, n_t)),
               series_steer_rad=rng.random((6, n_t)))
    out["example_roll_rad"][2, 5:] = np.nan  # a fall: NaN after it
    return out


def members(path) -> list[tuple[str, int, bytes]]:
    """Name, CRC and uncompressed bytes of every member, in order (the zip's timestamps aside)."""
    with zipfile.ZipFile(path) as z:
        return [(i.filename, i.CRC, z.read(i)) for i in z.infolist()]


def test_write_read_round_trip_is_exact(tmp_path):
    a = arrays()
    back = timesolution.read(timesolution.write(tmp_path / "LA_HS.npz", a))
    assert list(back) == list(a)  # the writers' key order is kept
    for k, v in a.items():
        assert back[k].dtype == np.asarray(v).dtype, k
        np.testing.assert_array_equal(back[k], v, err_msg=k)
    assert back["fell"].dtype == bool and str(back["method"]) == "LA"


def test_write_gives_the_bytes_of_numpys_writer(tmp_path):
    """The rule scripts wrote np.savez_compressed(path, **arrays): the module writes the same
    members (names, order, bytes), so moving the writers into it changes no output."""
    a = arrays("LN")
    np.savez_compressed(tmp_path / "before.npz", **a)
    timesolution.write(tmp_path / "after.npz", a)
    assert members(tmp_path / "after.npz") == members(tmp_path / "before.npz")


@pytest.mark.parametrize("key", list(timesolution.REQUIRED))
def test_check_refuses_a_missing_key(tmp_path, key):
    a = arrays()
    del a[key]
    path = tmp_path / "LA_HS.npz"
    with pytest.raises(timesolution.TimeSolutionError, match=f"missing key.*{key}"):
        timesolution.write(path, a)
    assert not path.exists()
    np.savez_compressed(path, **a)  # a file written around the module is refused on reading
    with pytest.raises(timesolution.TimeSolutionError, match=f"{path}: missing key.*{key}"):
        timesolution.read(path)


def test_check_refuses_wrong_shapes_dtypes_and_methods():
    bad_shape = dict(arrays(), steer_amp_rad=np.zeros((3, 4)))
    with pytest.raises(timesolution.TimeSolutionError, match=r"steer_amp_rad has shape \(3, 4\)"
                       r", expected \(4, 3\)"):
        timesolution.check(bad_shape)
    bad_example = dict(arrays(), example_roll_tight_rad=np.zeros((6, 10)))  # optional, n_t = 11
    with pytest.raises(timesolution.TimeSolutionError, match="example_roll_tight_rad"):
        timesolution.check(bad_example)
    with pytest.raises(timesolution.TimeSolutionError, match="fell is float64"):
        timesolution.check(dict(arrays(), fell=np.zeros((4, 3))))
    with pytest.raises(timesolution.TimeSolutionError, match="method 'XX'"):
        timesolution.check(arrays("XX"))


def test_merge_chunks_restores_the_grid_in_speed_order():
    full = arrays("NT", n_v=5)
    full["n_rhs"] = np.arange(15).reshape(5, 3)
    grid_keys = timesolution.CHUNK_GRID_KEYS
    examples = {k: v for k, v in full.items() if k.startswith(("example_", "series_"))}
    chunks = [dict(speed_index=idx, **{k: full[k][idx] for k in grid_keys},
                   **(examples if first else {}))
              for idx, first in ((np.array([3, 4]), False), (np.array([0, 1, 2]), True))]
    out = timesolution.merge_chunks(chunks, full["speed_m_s"], full["omega_rad_s"], "NT", "HS",
                                    [1, 3, 5], 100.0)
    timesolution.check(out)
    for k in grid_keys:
        np.testing.assert_array_equal(out[k], full[k], err_msg=k)
    assert out["example_roll_rad"] is examples["example_roll_rad"]
    with pytest.raises(timesolution.TimeSolutionError, match="do not cover the speed grid"):
        timesolution.merge_chunks(chunks[:1], full["speed_m_s"], full["omega_rad_s"], "NT", "HS",
                                  [1, 3, 5], 100.0)
    no_examples = {k: v for k, v in chunks[1].items() if not k.startswith("example_")}
    with pytest.raises(timesolution.TimeSolutionError, match="0 carry the example runs"):
        timesolution.merge_chunks([chunks[0], no_examples], full["speed_m_s"],
                                  full["omega_rad_s"], "NT", "HS", [1, 3, 5], 100.0)


def test_the_writers_of_the_time_files_use_the_module():
    """LA/LN (linear_time.py) and NT/NP (nonlinear_time.py) write through timesolution.write."""
    from pedalrepro import paths

    for name in ("linear_time.py", "nonlinear_time.py"):
        text = (paths.ROOT / "rules" / "scripts" / name).read_text()
        assert "timesolution.write(" in text and "np.savez" not in text, name

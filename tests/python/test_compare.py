"""compare(): the program's `symphong compare --json` for the same files, arrays as well as files, the FLIP
map as an array, closed-form errors, and refusals (ValueError / FileNotFoundError naming the input)."""
import json

import numpy as np
import pytest


def _pair(sym, tmp_path):
    rng = np.random.default_rng(5)
    ref = np.clip(rng.random((20, 30, 3)), 0.05, None).astype(np.float32)
    test = (ref * (1 + 0.2 * rng.standard_normal(ref.shape))).astype(np.float32).clip(0)
    sym.write_image(str(tmp_path / "ref.exr"), ref)
    sym.write_image(str(tmp_path / "test.exr"), test)
    return test, ref


def test_same_numbers_as_the_program(sym, cli, tmp_path):
    _pair(sym, tmp_path)
    args = [str(tmp_path / "test.exr"), str(tmp_path / "ref.exr")]
    program = json.loads(cli("compare", *args, "--json", "--regions", "0,0,10,10").stdout)
    module = sym.compare(*args, regions=[(0, 0, 10, 10)])
    for key in ("mse", "rmse", "relmse", "mean_ratio", "flip", "mse_rgb"):
        assert module["image"][key] == program["image"][key], key
        assert module["regions"][0][key] == program["regions"][0][key], key
    assert module["flip"] == program["flip"]
    assert module["flip_values"].shape == (20, 30)
    assert module["flip_values"].dtype == np.float32
    assert abs(float(module["flip_values"].mean()) - module["image"]["flip"]) < 1e-6


def test_arrays_and_closed_forms(sym):
    ref = np.full((8, 12, 3), 0.5, np.float32)
    same = sym.compare(ref, ref)
    assert same["image"]["mse"] == 0 and same["image"]["flip"] == 0
    assert not same["flip_values"].any()
    offset = sym.compare(ref + np.float32(0.1), ref, flip="off")
    assert offset["image"]["mse"] == pytest.approx(0.01, rel=1e-6)  # luminance weights sum to 1
    assert offset["image"]["mean_ratio"] == pytest.approx(1.2, rel=1e-6)
    assert offset["image"]["flip"] is None and "flip_values" not in offset
    var = np.full((8, 12, 3), 0.04, np.float32)
    biased = sym.compare(ref + np.float32(0.1), ref, variance=var, flip="off")
    assert biased["image"]["bias_std_error"] == pytest.approx(0.2 / np.sqrt(96), rel=1e-6)


def test_refusals(sym, tmp_path):
    ref = np.zeros((8, 12, 3), np.float32)
    with pytest.raises(ValueError, match="8 x 9"):
        sym.compare(np.zeros((9, 8, 3), np.float32), ref)
    with pytest.raises(FileNotFoundError, match="nothing.exr"):
        sym.compare(str(tmp_path / "nothing.exr"), ref)
    with pytest.raises(ValueError, match="--regions"):
        sym.compare(ref, ref, regions="0,0,20,20")
    with pytest.raises(ValueError):
        sym.compare(ref, ref, flip="sometimes")
    with pytest.raises(TypeError):
        sym.compare(ref, ref, colour=True)

"""render() in passes (time, target_error, pass_spp, checkpoint, resume): the one-pass image bit for bit,
a checkpoint resumed to the same image, refusals, and the target error's stop."""
import numpy as np
import pytest

SETTINGS = dict(spp=12, width=40, height=30, threads=2, progress=False)


def test_passes_give_the_one_pass_image(sym):
    once, stats = sym.render("cornell", **SETTINGS)
    assert stats["stop_reason"] == "spp" and stats["spp_reached"] == 12
    passes, stats = sym.render("cornell", pass_spp=5, **SETTINGS)
    assert np.array_equal(once, passes)
    assert stats["stop_reason"] == "spp" and stats["spp_reached"] == 12 and stats["relative_error"] > 0


def test_checkpoint_resumes_to_the_same_image(sym, tmp_path):
    once, _ = sym.render("cornell", **SETTINGS)
    path = str(tmp_path / "r.ckpt")
    first, stats = sym.render("cornell", pass_spp=4, checkpoint=path, **SETTINGS)
    assert stats["checkpoint"] == path and np.array_equal(once, first)
    again, stats = sym.render("cornell", checkpoint=path, resume=True, **SETTINGS)
    assert np.array_equal(once, again)
    with pytest.raises(ValueError, match="the checkpoint was made with seed 1, not 2"):
        sym.render("cornell", checkpoint=path, resume=True, seed=2, **SETTINGS)
    with pytest.raises(ValueError, match="a checkpoint is already there"):
        sym.render("cornell", checkpoint=path, **SETTINGS)
    with pytest.raises(ValueError, match="resume=True needs checkpoint=PATH"):
        sym.render("cornell", resume=True, **SETTINGS)


def test_target_error_stops_the_render(sym):
    img, stats = sym.render("cornell", spp=100000, width=24, height=24, target_error=0.05, threads=2, progress=False)
    assert stats["stop_reason"] == "target error"
    assert stats["relative_error"] <= 0.05
    assert 4 <= stats["spp_reached"] < 100000
